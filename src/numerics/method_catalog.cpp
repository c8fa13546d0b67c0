#include "numerics/method_catalog.hpp"

#include <algorithm>
#include <utility>

#include "numerics/method_list.hpp"

namespace cs {

namespace {

template <class Method>
MethodInfo info_of() {
  constexpr const MethodDescription& d = Method::description;
  return {std::string(d.name), d.order, std::string(d.properties),
          std::vector<std::string>(d.needs_split_parts.begin(), d.needs_split_parts.end()),
          d.force_evaluations_per_step, d.adaptive};
}

}  // namespace

// Built from the generated list (numerics/method_list.hpp), in each description's catalog
// position. (A function's static, not a global: no static initialisation order.)
const std::vector<MethodInfo>& method_catalog() {
  static const std::vector<MethodInfo> catalog = [] {
    std::vector<std::pair<int, MethodInfo>> listed;
    Methods::for_each([&]<class Method>() {
      listed.emplace_back(Method::description.catalog_position, info_of<Method>());
    });
    std::sort(listed.begin(), listed.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : a.second.name < b.second.name;
    });
    std::vector<MethodInfo> methods;
    for (auto& [position, info] : listed) methods.push_back(std::move(info));
    return methods;
  }();
  return catalog;
}

std::vector<std::string> missing_split_parts(const MethodInfo& method,
                                             const std::vector<std::string>& offered) {
  std::vector<std::string> missing;
  for (const std::string& part : method.needs_split_parts)
    if (std::find(offered.begin(), offered.end(), part) == offered.end()) missing.push_back(part);
  return missing;
}

const MethodInfo* find_method(std::string_view name) {
  const auto& all = method_catalog();
  auto it = std::find_if(all.begin(), all.end(), [&](const MethodInfo& m) { return m.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace cs
