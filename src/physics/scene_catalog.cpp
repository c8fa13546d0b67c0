#include "physics/scene_catalog.hpp"

#include <algorithm>

namespace cs {

const std::vector<SceneInfo>& scene_catalog() {
  static const std::vector<SceneInfo> catalog = builtin_scene_infos();
  return catalog;
}

const SceneInfo* find_scene(std::string_view name) {
  const auto& all = scene_catalog();
  auto it = std::find_if(all.begin(), all.end(), [&](const SceneInfo& s) { return s.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace cs
