// A step kernel: what a scene.K compiled at run time hands the program for the runs whose block
// runner the program already holds (engine/step_kernel_runner.hpp). Most of a kernel's compile
// went into instantiating the block runner for its scene (docs/performance.md, "First build of a
// new K"), though little of the runner depends on the scene. A step kernel holds only what does:
// the tile's step loop (the hot path, called once per chunk) and the scene's per-lane functions
// (a lane's start, its method coefficients, K at a state; called once per lane or per sample).
// The program runs the same BlockRunner over a proxy scene (engine/proxy_scene.hpp) whose
// members call this table.
//
// One step kernel serves every fixed-step method of its K: it holds a table per method, and its
// entry point (kStepKernelEntry, a StepKernelEntry) returns the one a run names. A physicist
// comparing methods on one K compiles once (docs/performance.md).
//
// Both sides lay the tile out alike: room for kStepKernelParamFields parameters and
// kStepKernelCoefFields coefficients whatever the scene and method use (LaneTile's field
// capacities), checked through tile_bytes. The kernel's key names the program that built it
// (kernel_cache.hpp), so a table never meets another build's runner; the checks catch a mistake
// in this file, not an attack.
#pragma once

#include <cstddef>
#include <cstdint>

namespace cs {

inline constexpr std::uint32_t kStepKernelAbi = 5;
inline constexpr const char* kStepKernelEntry = "contactsweep_step_kernel";
struct StepKernel;
// The table of the named method, or null where the kernel has none (an adaptive method).
using StepKernelEntry = const StepKernel* (*)(const char* method);
// The runner's tile: its lanes, and its room for a scene's parameters and a method's
// coefficients (contact_splitting6 has 31). A K with more parameters, or more than
// kStepKernelMaxDof degrees of freedom, gets a whole kernel as before.
inline constexpr int kStepKernelWidth = 64;
inline constexpr int kStepKernelParamFields = 16;
inline constexpr int kStepKernelCoefFields = 32;
inline constexpr int kStepKernelMaxDof = 3;
// The runner's room for a run's observables (measures as formulas); a run with more gets a
// whole kernel.
inline constexpr int kStepKernelMaxObservables = 16;

// The energy trap's uses of K (physics/energy_wells.hpp; engine/mappers/energy_trap.hpp), in a
// kernel built for a basin map that uses the trap (K = Σp²/2 + V(q) + k·z without t); else
// `used` is false and the entries null. The wells' search is most of such a kernel's compile
// (0.4 of 0.8 s): a K's other runs build a kernel without it. E = K(q, p, 0) of a tile's W lanes
// for its screen, from its q, p and parameter fields (field-major, W lanes each), or with
// uniform_params where not null; V(q); the box and the wells of a parameter set (a
// BasinBox<dof> and a Wells<dof> of the program's, filled here); the minimum of the well
// holding q.
struct StepKernelTrap {
  bool used = false;
  void (*tile_energy)(const double* q, const double* p, const double* param_fields,
                      const double* uniform_params, double* energy) = nullptr;
  double (*potential)(const double* q, const double* params) = nullptr;
  void (*box)(const double* params, const void* positions, const double* widen, double e0,
              double h, void* box) = nullptr;
  void (*wells)(const double* params, const void* box, double h, void* wells) = nullptr;
  bool (*well_bottom)(const double* params, const void* box, double h, const double* q,
                      const void* wells, double* minimum) = nullptr;
};

// The run's measures as formulas ([measures] observe, observe_window, stop;
// engine/measures/observables.hpp), in a kernel built for a run that has them; else
// `observables` is 0, `stop` false and the entries null. The kernel's source holds the generated
// formulas, so its key is the formulas' too. One lane's values, its stop's condition and exit
// channel, at the state (q, p, z), time t and λ = exp(ln λ) (computed by the runner where
// reads_lambda); values[k] is observable k in the spec's order. What the formulas do after every
// step (the stop's flags, a window without trajectory) runs in the kernel's step loop
// (StepKernel::advance_watched) on the runner's FormulaSteps, of steps_bytes.
struct StepKernelFormulas {
  int observables = 0;
  bool stop = false;
  bool reads_lambda = false;
  std::size_t steps_bytes = 0;
  void (*observe)(const double* q, const double* p, double z, double t, double lambda,
                  const double* params, double* values) = nullptr;
  bool (*stops)(const double* q, const double* p, double z, double t, double lambda,
                const double* params) = nullptr;
  double (*exit)(const double* q, const double* p, double z, double t, double lambda,
                 const double* params) = nullptr;
};

// Parameters and coefficients travel as kStepKernelParamFields and kStepKernelCoefFields
// doubles, of which the scene's and the method's own are the first; lane states as
// LaneState<dof> (numerics/lane_state.hpp), the same type on both sides.
struct StepKernel {
  std::uint32_t abi;
  const char* method;  // its method's name (the spec's integrator.method)
  int dof;
  int param_fields;  // the scene's Params (its parameters, or one unused field where it has none)
  int coef_fields;   // the method's Coef
  std::size_t tile_bytes;
  bool kz_constant;     // K_z constant: a lane's breakdown flag is never set
  bool time_dependent;  // K reads t: the step loop reads the lanes' step counts
  bool carries_z, carries_mu;  // the fields of a lane its step writes besides q, p (and broken)
  // The tile (LaneTile of the program's proxy scene) `steps` steps on; parameters and
  // coefficients from the tile's lanes when the kernel was built for per-lane parameters.
  void (*advance)(void* tile, int steps, const double* uniform_params, const double* uniform_coef,
                  double t_start, double h);
  // As advance, with the formulas' work after every step (formula_steps.hpp's
  // formula_after_step) on tile `which` (0 main, 1 finisher) and the runner's FormulaSteps
  // `steps_state`; null without formulas.
  void (*advance_watched)(void* tile, int steps, const double* uniform_params,
                          const double* uniform_coef, double t_start, double h, int which,
                          void* steps_state);
  // One step of one lane (Method::step), for the stop's scalar rerun.
  void (*step)(void* lane_state, const double* params, const double* coef);
  void (*start)(void* lane_state, const double* params);  // Method::start
  void (*coefficients)(double h, const double* params, const void* lane_state, double* coef);
  bool (*breaks_down)(const double* coef);
  bool (*defined_at)(const void* lane_state, const double* params);  // engine/lane_health.hpp
  double (*K)(const double* q, const double* p, double z, double t, const double* params);
  double (*log_lambda)(const void* lane_state);
  bool (*diverged)(const double* q, const double* p);
  void (*natural_frequencies)(const double* params, double* omega);
  StepKernelTrap trap;
  StepKernelFormulas formulas;
};

}  // namespace cs
