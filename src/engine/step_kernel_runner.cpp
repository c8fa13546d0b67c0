#include "engine/step_kernel_runner.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "engine/block_runner.hpp"
#include "engine/mappers/mapper_choice.hpp"
#include "engine/proxy_scene.hpp"
#include "formula/custom_scene.hpp"
#include "formula/measure_formulas.hpp"
#include "numerics/method_list.hpp"

namespace cs {
namespace {

template <int D>
using ProxyTile = LaneTile<ProxyScene<D>, ProxyMethod, kStepKernelWidth>;

std::size_t proxy_tile_bytes(int dof) {
  switch (dof) {
    case 1: return sizeof(ProxyTile<1>);
    case 2: return sizeof(ProxyTile<2>);
    case 3: return sizeof(ProxyTile<3>);
    default: return 0;
  }
}

int coefficient_count(const std::string& method) {
  int count = kStepKernelCoefFields + 1;  // an unknown method: no step kernel
  Methods::with_named(method, [&]<class Method>() {
    count = static_cast<int>(sizeof(typename Method::template Coef<double>) / sizeof(double));
  });
  return count;
}

// The runner reads nothing of the carried state but the tangent (none here): the kernel's step
// loop carries what the plan asks, so one runner per count of degrees of freedom, parameter
// layout, whether it maps basins and whether it has measures as formulas. A basin map's runner
// holds every mapper, the trap with its uses of K in the kernel (engine/proxy_scene.hpp); a
// runner with formulas, the tracker whose values the kernel computes (ProxyFormulas).
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

template <int D>
void run_proxy(const RunPlan& plan, BlockResults& results) {
  if (has_measure_formulas(plan.spec.measures)) run_proxy<D, true>(plan, results);
  else run_proxy<D, false>(plan, results);
}

// Measures as formulas a step kernel can hold: as many observables as the runner has room for.
bool formulas_fit_step_kernel(const RunPlan& plan) {
  return plan.observe.observables <= kStepKernelMaxObservables;
}

// The table's formulas are the plan's, laid out for this program's runner.
bool formulas_match(const StepKernelFormulas& f, const RunPlan& plan) {
  const bool any = plan.observe.observables > 0 || plan.observe.stop;
  return f.observables == plan.observe.observables && f.stop == plan.observe.stop &&
         (!any || (f.steps_bytes == sizeof(FormulaSteps<kStepKernelMaxObservables, kStepKernelWidth>) &&
                   f.observe != nullptr && f.stops != nullptr && f.exit != nullptr));
}

}  // namespace

bool uses_energy_trap(const RunPlan& plan) {
  return plan.map.basin >= 0 && mappers_of(plan).trap && plan.spec.custom &&
         plan.spec.custom->formula.traits.energy_trap_form();
}

bool runs_on_step_kernel(const std::vector<const RunPlan*>& plans) {
  for (const RunPlan* plan : plans) {
    // A built-in scene's runs are compiled ahead of time but those with measures as formulas
    // (and its basin maps, whose energy trap and fixed points read the scene's own type).
    const bool formulas = has_measure_formulas(plan->spec.measures);
    if (!plan->spec.custom && !(formulas && plan->map.basin < 0)) return false;
    if (plan->method.adaptive || plan->carry.tangent ||
        (formulas && !formulas_fit_step_kernel(*plan)) ||
        plan->scene.dof > kStepKernelMaxDof ||
        plan->scene.parameters.size() > static_cast<std::size_t>(kStepKernelParamFields) ||
        coefficient_count(plan->spec.method) > kStepKernelCoefFields)
      return false;
  }
  return !plans.empty();
}

void check_step_kernel(const StepKernel& kernel, const RunPlan& plan) {
  if (kernel.abi != kStepKernelAbi || kernel.method == nullptr ||
      std::string_view(kernel.method) != plan.spec.method || kernel.dof != plan.scene.dof ||
      kernel.param_fields < static_cast<int>(plan.scene.parameters.size()) ||
      kernel.param_fields > kStepKernelParamFields ||
      kernel.coef_fields != coefficient_count(plan.spec.method) ||
      kernel.tile_bytes != proxy_tile_bytes(plan.scene.dof) ||
      kernel.trap.used != uses_energy_trap(plan) ||
      !formulas_match(kernel.formulas, plan) ||
      (kernel.advance_watched != nullptr) != has_measure_formulas(plan.spec.measures) ||
      (kernel.step != nullptr) != plan.observe.stop)
    throw std::logic_error("the step kernel of scene.K does not match this program's runner");
}

void run_on_step_kernel(const RunPlan& plan, BlockResults& results) {
  const BoundStepKernel bound(*plan.step_kernel, static_cast<int>(plan.scene.parameters.size()));
  switch (plan.scene.dof) {
    case 1: return run_proxy<1>(plan, results);
    case 2: return run_proxy<2>(plan, results);
    case 3: return run_proxy<3>(plan, results);
    default: throw std::logic_error("no step-kernel runner for " + std::to_string(plan.scene.dof) +
                                    " degrees of freedom");
  }
}

}  // namespace cs
