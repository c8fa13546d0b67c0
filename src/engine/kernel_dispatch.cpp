// The dispatch to the built-in kernels: the one place where run-time names meet template
// instantiations (scene × method × carried state × uniform parameters). Kept apart from
// run_plan.cpp because it holds every instantiation of the block runner: the heavy compile.
#include <memory>
#include <stdexcept>

#include "engine/block_runner.hpp"
#include "engine/run_plan.hpp"
#include "numerics/method_list.hpp"
#include "physics/coupled_oscillators.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/double_well.hpp"
#include "physics/z2_damping.hpp"

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

template <class Method>
void run_scene(const RunPlan& plan, BlockResults& results) {
  const auto& name = plan.scene.name;
  if (name == "damped_oscillator") return run_with<DampedOscillator, Method>(plan, results);
  if (name == "z2_damping") return run_with<Z2Damping, Method>(plan, results);
  if (name == "double_well") return run_with<DoubleWell, Method>(plan, results);
  if (name == "coupled_oscillators") return run_with<CoupledOscillators, Method>(plan, results);
  throw std::logic_error("no kernel for scene " + name);
}

}  // namespace

void run_block(const RunPlan& plan, BlockResults& results) {
  if (plan.custom_kernel != nullptr) return plan.custom_kernel(plan, results);
  const auto run = [&]<class Method>() { run_scene<Method>(plan, results); };
  if (!Methods::with_named(plan.method.name, run))
    throw std::logic_error("no kernel for method " + plan.method.name);
}

}  // namespace cs
