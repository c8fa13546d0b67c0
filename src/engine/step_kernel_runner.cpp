#include "engine/step_kernel_runner.hpp"

#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/proxy_runner.hpp"
#include "engine/scene_form.hpp"
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
  return plan.map.basin >= 0 && mappers_of(plan).trap && energy_trap_form(plan.spec, plan.scene);
}

bool runs_on_step_kernel(const std::vector<const RunPlan*>& plans) {
  for (const RunPlan* plan : plans) {
    // A built-in scene's runs are compiled ahead of time but those with measures as formulas.
    const bool formulas = has_measure_formulas(plan->spec.measures);
    if (!plan->spec.custom && !formulas) return false;
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
      kernel.carries_mu != plan.carry.mu || !formulas_match(kernel.formulas, plan) ||
      (kernel.advance_watched != nullptr) != has_measure_formulas(plan.spec.measures) ||
      (kernel.step != nullptr) != plan.observe.stop)
    throw std::logic_error("the step kernel of the run's scene does not match this program's runner");
}

void run_on_step_kernel(const RunPlan& plan, BlockResults& results) {
  const BoundStepKernel bound(*plan.step_kernel, static_cast<int>(plan.scene.parameters.size()));
  if (has_measure_formulas(plan.spec.measures)) run_proxy_with_formulas(plan, results);
  else run_proxy_without_formulas(plan, results);
}

void run_proxy_without_formulas(const RunPlan& plan, BlockResults& results) {
  run_proxy<false>(plan, results);
}

}  // namespace cs
