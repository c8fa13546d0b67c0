// Everything the engine decides once per run from a validated spec: what state to carry, how
// often to look at the lanes, which datasets to produce, and the kernel instantiation to use.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/grid.hpp"
#include "engine/lane_status.hpp"
#include "engine/measures/observe_plan.hpp"
#include "engine/results.hpp"
#include "engine/recurrence/recurrence_search.hpp"
#include "model/run_spec.hpp"
#include "numerics/lane_state.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

struct StepKernel;  // engine/step_kernel.hpp

// The `status` of a cell no rank wrote: the file's fill value, never produced by a lane.
inline constexpr int kStatusNotComputed = 255;

// Where each measure's values go: a column index, or −1 when not requested.
struct ColumnMap {
  int status = -1;
  std::vector<int> final_vars;  // per catalog variable (lambda → final_log_lambda), −1 if not
  int final_H = -1;
  std::vector<int> traj_vars;   // per catalog variable, −1 if no trajectory
  int traj_H = -1;
  int basin = -1, settle_time = -1;
  // internal, per block: the distinct (q.., p.., period) its settled lanes settled on, each
  // `width` values (engine/settlement_records.hpp)
  int basin_records = -1;
  int trap_verdict = -1;  // internal, per block: how many lanes had each TrapVerdict
  // internal, where the recurrence mapper runs: a lane's record (RecurrenceSearch) and why it
  // ended undecided (UndecidedReason)
  int basin_cells = -1, undecided_reason = -1;
  int sync_r = -1, sync_phase_drift = -1, sync_freq_ratio = -1, sync_amplitude = -1;
  int lyapunov = -1;
};

// The `basin` dataset's long_name when its labels are numbers 1..n (LabelRule::numbered).
inline constexpr const char* kNumberedBasinLongName =
    "basin of attraction: the attractor_label of the attractor reached (0: undecided)";

// What a lane needs to find its attractor (engine/mappers/; see BasinMeasure).
struct AttractorSearch {
  std::int64_t sample_steps = 0;  // steps between samples: the period's, or the look interval
  int dwell_samples = 0;          // consecutive samples near the attractor that settle a lane
  int max_period = 1;
  double tolerance = 0.0;
  std::vector<double> angle_period;  // per phase-space variable q.., p..: 0 if not an angle
  // An adaptive method's stroboscopic map: its lanes have no common steps, so the map's samples
  // are counted (sample_steps = 1) and taken at t_start + k·period, k = 0 … strobe_last, from
  // the steps' dense output (engine/dense_samples.hpp).
  bool dense_strobe = false;
  std::int64_t strobe_last = -1;
};

struct RunPlan {
  const RunSpec& spec;
  const SceneInfo& scene;
  const MethodInfo& method;
  Grid grid;
  Carry carry{};
  int chunk = 32;                 // steps between looks at the lanes (divides trajectory.every)
  std::int64_t sync_first_step = 0, sync_last_step = -1;  // the sync window, on looks only
  std::int64_t samples = 0;       // trajectory samples per point (0: none)
  std::vector<double> sample_times;
  AttractorSearch attractors;
  // The lyapunov measure's first tangent (1 in each chosen q.., p.., z; engine/measures/) and
  // ln of its norm.
  std::vector<double> lyapunov_seed;
  double lyapunov_log_norm0 = 0.0;
  RecurrenceSearch recurrence;
  std::vector<ColumnSpec> columns;
  ColumnMap map;
  ObservePlan observe;  // observe and stop (engine/measures/)
  // Flat index of this plan's first point in the whole grid: a run over several step sizes
  // has one plan per h, each for its contiguous slice of the grid (step_size_slices).
  std::int64_t point_offset = 0;
  // The kernel of a custom scene (kernel_build/), built and loaded for this run; built-in
  // scenes are dispatched by name instead.
  void (*custom_kernel)(const RunPlan&, BlockResults&) = nullptr;
  // A scene.K's step kernel (engine/step_kernel.hpp) where the program's runner does the rest
  // (runs_on_step_kernel); it then runs the blocks, not custom_kernel.
  const StepKernel* step_kernel = nullptr;

  RunPlan(const RunSpec& spec, const SceneInfo& scene, const MethodInfo& method);

 private:
  friend void plan_observables(RunPlan& plan);
  int add_column(DatasetSpec dataset, std::int64_t width = 1, bool internal = false);
  void add_basin_columns(const BasinMeasure& basin);
};

// One plan per step size when the first grid axis is h (each with that h, the remaining axes
// and its point_offset), else the plan of the whole grid. `specs` keeps the slices' specs alive.
std::vector<std::unique_ptr<RunPlan>> step_size_slices(const RunSpec& spec, const SceneInfo& scene,
                                                       const MethodInfo& method,
                                                       std::vector<std::unique_ptr<RunSpec>>& specs);

// Whether an adaptive method's lanes take samples inside their steps (a trajectory, sync, a
// stroboscopic map, an observe window without trajectory): they need the steps' continuous
// extension (engine/dense_samples.hpp). A kernel built at run time for a plan without them
// compiles no dense output (BlockRunner's DenseOutput). Inline: kernels call it too, and the
// program exports none of its own functions to them but the engine's (engine_exports.list).
// An observe window's last step is never below 0 (observe_plan.cpp refuses an empty window).
inline bool samples_inside_steps(const RunPlan& plan) {
  return plan.samples > 0 || plan.map.sync_r >= 0 ||
         (plan.attractors.dense_strobe && plan.map.basin >= 0) || plan.observe.window_every_step;
}

// Integrates the points of `results.range` and fills `results`. Thread-safe for distinct blocks.
// (engine/kernel_dispatch.cpp)
void run_block(const RunPlan& plan, BlockResults& results);

}  // namespace cs
