// The program's side of a step kernel (step_kernel.hpp): which runs of a scene.K can use one, and
// the block runner over the proxy scene that runs them. Compiled once into the program, so that a
// new K's first run compiles only its step loop and its per-lane functions (docs/performance.md).
#pragma once

#include <vector>

#include "engine/run_plan.hpp"
#include "engine/step_kernel.hpp"

namespace cs {

// Whether the runs of `plans` (a run's step-size slices) need nothing of a K beyond a step
// kernel: a fixed-step method, no lyapunov tangent, at most kStepKernelMaxObservables measures
// as formulas, at most kStepKernelMaxDof degrees of freedom and the tile's room for the
// parameters and the method's coefficients. A built-in scene's run with measures as formulas and
// no basin map too: its other runs are compiled ahead of time.
bool runs_on_step_kernel(const std::vector<const RunPlan*>& plans);

// Whether the plan's basin map uses the energy trap: its exact_trap, where K has one
// (K = Σp²/2 + V(q) + k·z, no t). Its step kernel is then built with the trap's entries
// (StepKernelTrap), which a K's other runs do without.
bool uses_energy_trap(const RunPlan& plan);

// Throws std::logic_error when `kernel` is not the table this program's runner expects for `plan`.
void check_step_kernel(const StepKernel& kernel, const RunPlan& plan);

// Integrates `results.range` with the block runner over the proxy scene, the plan's step kernel
// (RunPlan::step_kernel) doing the scene's work. Thread-safe for distinct blocks.
void run_on_step_kernel(const RunPlan& plan, BlockResults& results);

}  // namespace cs
