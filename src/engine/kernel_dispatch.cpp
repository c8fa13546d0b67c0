// The dispatch to the built-in kernels: the one place where run-time names meet template
// instantiations (scene × method × carried state × uniform parameters). Kept apart from
// run_plan.cpp because it holds every instantiation of the block runner: the heavy compile.
#include <memory>
#include <stdexcept>

#include "engine/block_runner.hpp"
#include "engine/run_plan.hpp"
#include "numerics/method_list.hpp"
#include "physics/builtin_scenes.hpp"  // generated from physics/scenes.toml

namespace cs {
namespace {

template <Scene S, class Method>
void run_with(const RunPlan& plan, BlockResults& results) {
  auto go = [&]<Carry carry>() {
    if (plan.grid.uniform_parameters())
      std::make_unique<BlockRunner<S, Method, carry, true>>(plan, results)->run();
    else
      std::make_unique<BlockRunner<S, Method, carry, false>>(plan, results)->run();
  };
  if (plan.carry.mu) go.template operator()<Carry{true, true}>();
  else if (plan.carry.z) go.template operator()<Carry{true, false}>();
  else go.template operator()<Carry{false, false}>();
}

// The built-in scene of that name (BuiltinScenes: the catalog's list), run with Method.
template <class Method, class... Scenes>
void run_scene(const RunPlan& plan, BlockResults& results, SceneList<Scenes...>) {
  const bool found = ((plan.scene.name == Scenes::name
                           ? (run_with<Scenes, Method>(plan, results), true)
                           : false) || ...);
  if (!found) throw std::logic_error("no kernel for scene " + plan.scene.name);
}

}  // namespace

void run_block(const RunPlan& plan, BlockResults& results) {
  if (plan.custom_kernel != nullptr) return plan.custom_kernel(plan, results);
  const auto run = [&]<class Method>() { run_scene<Method>(plan, results, BuiltinScenes{}); };
  if (!Methods::with_named(plan.method.name, run))
    throw std::logic_error("no kernel for method " + plan.method.name);
}

}  // namespace cs
