// The dispatch to the built-in kernels: the one place where run-time names meet template
// instantiations. The method is picked here by a fold over the generated method list; the scene,
// carried state and parameter layout inside run_builtin_scene<Method>, instantiated per method in
// generated sources of their own (engine/builtin_kernels.hpp).
#include <stdexcept>

#include "engine/builtin_kernels.hpp"
#include "engine/run_plan.hpp"
#include "engine/step_kernel_runner.hpp"
#include "numerics/method_list.hpp"

namespace cs {

void run_block(const RunPlan& plan, BlockResults& results) {
  if (plan.step_kernel != nullptr) return run_on_step_kernel(plan, results);
  if (plan.custom_kernel != nullptr) return plan.custom_kernel(plan, results);
  const auto run = [&]<class Method>() { run_builtin_scene<Method>(plan, results); };
  if (!Methods::with_named(plan.method.name, run))
    throw std::logic_error("no kernel for method " + plan.method.name);
}

}  // namespace cs
