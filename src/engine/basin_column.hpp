// A basin map's `basin` column between a block's end and the file: the provisional labels
// (numbers of the block's settlement records) are kept to the end of the run, when the
// attractor table of every block turns them into labels. Held as doubles they cost 8 bytes a
// point of each rank's blocks; once the block is saved in the journal they are held compact
// (CompactColumn: 1 byte a point while a block has under 128 distinct settlements, as on every
// map of few attractors) and expanded one block at a time by what reads them at the end. Where
// the recurrence mapper runs, its per-point columns are held compact from then on too
// (recurrence/lane_records.hpp), and the provisional values number the block's entries there.
#pragma once

#include "engine/recurrence/lane_records.hpp"
#include "engine/results.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// After the block is saved (or loaded from the journal): nothing reads its `basin` as doubles
// until the end. It rewrites `basin` and, on a recurrence map, `basin_records`, `basin_cells` and
// `undecided_reason` (lane_records.hpp): no other thread reads those of a saved block (the output
// stream reads only the columns it writes).
inline void compact_basin(const RunPlan& plan, BlockResults& block) {
  if (plan.map.basin < 0 || block.basin_compacted) return;
  compact_recurrence_columns(plan, block);  // reads and renumbers the provisional values
  auto& column = block.columns[static_cast<std::size_t>(plan.map.basin)];
  block.compact_basin.assign(column);
  std::vector<double>().swap(column);
  block.basin_compacted = true;
}

// The block's `basin` as doubles while it lives (nothing to do for a block never compacted);
// compacted again at its end, with what was written into it if `written`.
class ExpandedBasin {
 public:
  ExpandedBasin(const RunPlan& plan, BlockResults& block, bool written = false)
      : block_(block), index_(static_cast<std::size_t>(plan.map.basin)),
        active_(plan.map.basin >= 0 && block.basin_compacted), written_(written) {
    if (active_) block.compact_basin.expand(block.columns[index_]);
  }
  ~ExpandedBasin() {
    if (!active_) return;
    if (written_) block_.compact_basin.assign(block_.columns[index_]);
    std::vector<double>().swap(block_.columns[index_]);
  }
  ExpandedBasin(const ExpandedBasin&) = delete;
  ExpandedBasin& operator=(const ExpandedBasin&) = delete;

 private:
  BlockResults& block_;
  std::size_t index_;
  bool active_, written_;
};

}  // namespace cs
