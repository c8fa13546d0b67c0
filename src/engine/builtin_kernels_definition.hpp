// The definition of run_builtin_scene (builtin_kernels.hpp): the block runner instantiated for
// every built-in scene, carried state and parameter layout, for one method. Included only by the
// generated per-method sources (engine/builtin_kernels.cmake).
#pragma once

#include <memory>
#include <stdexcept>

#include "engine/block_runner.hpp"
#include "engine/builtin_kernels.hpp"
#include "physics/builtin_scenes.hpp"  // generated from physics/scenes.toml

namespace cs {
namespace builtin_kernels {

template <Scene S, class Method>
void run_with(const RunPlan& plan, BlockResults& results) {
  auto go = [&]<Carry carry>() {
    if (plan.grid.uniform_parameters())
      std::make_unique<BlockRunner<S, Method, carry, true>>(plan, results)->run();
    else
      std::make_unique<BlockRunner<S, Method, carry, false>>(plan, results)->run();
  };
  // An adaptive method always carries z and ln λ (RunPlan): one carried state to build.
  if constexpr (adaptive_method<Method>()) {
    if (!(plan.carry.z && plan.carry.mu)) throw std::logic_error("an adaptive run carries z and ln lambda");
    go.template operator()<Carry{true, true}>();
  } else if (plan.carry.mu) {
    go.template operator()<Carry{true, true}>();
  } else if (plan.carry.z) {
    go.template operator()<Carry{true, false}>();
  } else {
    go.template operator()<Carry{false, false}>();
  }
}

// The built-in scene of that name (BuiltinScenes: the catalog's list), run with Method.
template <class Method, class... Scenes>
void run_scene(const RunPlan& plan, BlockResults& results, SceneList<Scenes...>) {
  const bool found = ((plan.scene.name == Scenes::name
                           ? (run_with<Scenes, Method>(plan, results), true)
                           : false) || ...);
  if (!found) throw std::logic_error("no kernel for scene " + plan.scene.name);
}

}  // namespace builtin_kernels

template <class Method>
void run_builtin_scene(const RunPlan& plan, BlockResults& results) {
  builtin_kernels::run_scene<Method>(plan, results, BuiltinScenes{});
}

}  // namespace cs
