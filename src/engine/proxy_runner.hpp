// The block runner over the proxy scene (engine/proxy_scene.hpp), for the runs of a step kernel
// (step_kernel_runner.hpp). One runner per count of degrees of freedom, parameter layout,
// whether it maps basins and whether it has measures as formulas: the runs without formulas are
// instantiated in step_kernel_runner.cpp, those with them in proxy_runner_formulas.cpp, two
// files so that the program's build compiles them side by side (in one, the file took 36 s).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "engine/block_runner.hpp"
#include "engine/mappers/mapper_choice.hpp"
#include "engine/proxy_scene.hpp"

namespace cs {

// The runner reads nothing of the carried state but the tangent (none here): the kernel's step
// loop carries what the plan asks. A basin map's runner holds every mapper, the trap with its
// uses of K in the kernel; a runner with formulas, the tracker whose values the kernel computes
// (ProxyFormulas).
template <int D, bool Uniform, bool Basins, bool Formulas>
void run_proxy(const RunPlan& plan, BlockResults& results) {
  constexpr MapperChoice mappers = Basins ? kEveryMapper : MapperChoice{false, false, false, false};
  using M = std::conditional_t<Formulas, ProxyFormulas, NoMeasureFormulas>;
  using Runner = BlockRunner<ProxyScene<D>, ProxyMethod, Carry{false, false}, Uniform, M, mappers,
                             true>;
  std::make_unique<Runner>(plan, results)->run();
}

template <int D, bool Formulas>
void run_proxy(const RunPlan& plan, BlockResults& results) {
  const bool uniform = plan.grid.uniform_parameters(), basins = plan.map.basin >= 0;
  if (uniform && basins) run_proxy<D, true, true, Formulas>(plan, results);
  else if (uniform) run_proxy<D, true, false, Formulas>(plan, results);
  else if (basins) run_proxy<D, false, true, Formulas>(plan, results);
  else run_proxy<D, false, false, Formulas>(plan, results);
}

template <bool Formulas>
void run_proxy(const RunPlan& plan, BlockResults& results) {
  switch (plan.scene.dof) {
    case 1: return run_proxy<1, Formulas>(plan, results);
    case 2: return run_proxy<2, Formulas>(plan, results);
    case 3: return run_proxy<3, Formulas>(plan, results);
    default: throw std::logic_error("no step-kernel runner for " + std::to_string(plan.scene.dof) +
                                    " degrees of freedom");
  }
}

// The plan's step kernel bound to the thread (BoundStepKernel) by the caller.
void run_proxy_without_formulas(const RunPlan& plan, BlockResults& results);
void run_proxy_with_formulas(const RunPlan& plan, BlockResults& results);

}  // namespace cs
