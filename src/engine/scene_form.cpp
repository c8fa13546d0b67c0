#include "engine/scene_form.hpp"

#include <string>

#include "formula/custom_scene.hpp"
#include "physics/builtin_scenes.hpp"  // generated from physics/scenes.toml
#include "physics/energy_wells.hpp"

namespace cs {
namespace {

template <class... Scenes>
bool builtin_energy_trap_form(const std::string& name, SceneList<Scenes...>) {
  return ((name == Scenes::name && has_energy_trap<Scenes>()) || ...);
}

template <class... Scenes>
bool builtin_reads_time(const std::string& name, SceneList<Scenes...>) {
  return ((name == Scenes::name && time_dependent<Scenes>()) || ...);
}

}  // namespace

bool energy_trap_form(const RunSpec& spec, const SceneInfo& scene) {
  if (spec.custom) return spec.custom->formula.traits.energy_trap_form();
  return builtin_energy_trap_form(scene.name, BuiltinScenes{});
}

bool reads_time(const RunSpec& spec, const SceneInfo& scene) {
  if (spec.custom) return spec.custom->formula.traits.time_dependent;
  return builtin_reads_time(scene.name, BuiltinScenes{});
}

}  // namespace cs
