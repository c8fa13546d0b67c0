// What a run with measures as formulas ([measures] observe, observe_window, stop) writes and
// when its samples count: decided once per run (plan_observables, from RunPlan's constructor).
// The values come from engine/measures/observables.hpp in the kernel.
#pragma once

#include <cstdint>
#include <vector>

namespace cs {

struct RunPlan;

// A stopped lane's exit, in the basin machinery: a pseudo-attractor of this period whose point
// is (channel, 0, …, 0). The attractor table numbers exits before attractors
// (attractor_table.cpp), and the file's attractor_period says −1 for them.
inline constexpr int kExitPeriod = -1;

struct ObservePlan {
  int observables = 0;
  // Per observable, the column of final_<name>, traj_<name> (−1 without trajectory) and of
  // mean_, min_, max_<name> (−1 without observe_window).
  std::vector<int> final_value, trajectory, mean, min, max;
  bool window = false;
  bool window_every_step = false;  // no trajectory: every step's state is a sample
  std::int64_t window_first = 0, window_last = -1;  // the samples' steps n in the window
  bool stop = false;
  bool exits = false;  // stop.label or stop.exits given: stop_exit is written
  int stop_time = -1, stop_exit = -1;
};

// Adds the columns of observe and stop to `plan` and what its kernel must carry (z, ln λ).
void plan_observables(RunPlan& plan);

}  // namespace cs
