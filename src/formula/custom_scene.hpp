// A scene written in the spec as a formula (scene.K), with what the rest of the program needs to
// treat it like a built-in one: its run-time description (SceneInfo, as the catalog gives for
// built-ins) and its generated C++ header (compiled by kernel_build/).
#pragma once

#include <memory>
#include <string>

#include "formula/k_formula.hpp"
#include "model/run_spec.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

struct CustomScene {
  KFormula formula;
  SceneInfo info;
  std::string struct_name;  // of the generated scene, in namespace cs
  std::string header;       // its generated source
};

// From scene.K and scene.label; throws InputError (messages start with "scene.K: ").
std::shared_ptr<const CustomScene> make_custom_scene(const std::string& K, const std::string& label);

// The scene a validated spec runs: its custom scene, or the catalog's built-in.
const SceneInfo& scene_of(const RunSpec& spec);

}  // namespace cs
