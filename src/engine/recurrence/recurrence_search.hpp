// What the recurrence mapper needs from the run (RunPlan::recurrence): whether it runs, its grid
// of cells over phase space and the thresholds of its state machine (recurrence_tracker.hpp).
// Plain data, filled in by plan_recurrence() from measures.basin (README, "Basins of any
// system").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/run_spec.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

struct RecurrenceSearch {
  bool enabled = false;
  std::string why_off;                // when not enabled: why
  bool period_on_autonomous = false;  // measures.basin.period given, but K does not read t
  // Per phase-space variable q.., p..: the box, the cells' side (an angle's: its period over a
  // whole number of cells), the number of cells, the angle's period (0: not an angle).
  std::vector<double> lower, upper, cell_size, angle_period;
  std::vector<std::int64_t> cells;
  std::int64_t recurrences = 100, locate = 1000, max_lost = 20, max_cells = 16384;
  // A settled lane's record (RunPlan::map.basin_cells): its representative (smallest located
  // key), its located cells' count and a bottom-k sketch of them (NaN where fewer).
  static constexpr int kSketch = 8;
  static constexpr int kRecordWidth = 2 + kSketch;
};

// Why a lane ended undecided (RunPlan::map.undecided_reason), as the summary counts them.
enum class UndecidedReason : int {
  decided = 0,
  no_recurrence = 1,   // still finding new cells at t_end
  not_located = 2,     // recurred, but t_end came before `locate` samples
  left_box = 3,        // outside the box for more than max_lost samples in a row
  too_many_cells = 4,  // visited max_cells cells without recurring
  diverged = 5,        // the lane's status: diverged, broke down or not finite
  not_tracked = 6,     // the recurrence mapper never looked at it (the energy trap's lane)
};
inline constexpr int kUndecidedReasons = 7;

// The recurrence mapper's settings for this run: off unless asked for where K proves every
// attractor a fixed point (K = Σp²/2 + V(q) + k·z without t). Throws InputError when the box
// holds more cells than keys can name (2^53).
RecurrenceSearch plan_recurrence(const RunSpec& spec, const SceneInfo& scene,
                                 const std::vector<double>& angle_period);

// The centre of a cell (angles in [0, period)), as CellGrid::centre.
std::vector<double> cell_centre(const RecurrenceSearch& r, std::uint64_t key);

}  // namespace cs
