// Basin mappers: how a lane's attractor is recognised on line (Attractors.jl's AttractorMapper).
// Each mapper is one file in this folder; the block runner knows them only through MapperSet
// (mapper_set.hpp), which calls them in a fixed order, and every mapper writes the same thing
// when a lane settles: a point of its attractor and the period (Settlement). What is computed on
// the settled points is written once for all mappers: the attractor table and its labels
// (attractor_table.cpp, label_rule.hpp), fractions and statistics (strip_statistics.cpp).
//
// A mapper M, built from the plan (RunPlan) and the runner's uniform parameters, provides
//   bool active() const                   whether this run uses it (the others cost nothing);
//   void clear(int slot)                  the slot is empty: forget its lane;
//   void look(int slot, std::int64_t n, const LaneState<D>& x, const Params& c, Settlement& s)
//        scalar: the healthy lane in `slot` at step n, not settled yet; may settle it. Called at
//        load (n = 0), whenever the screen flags the lane, at the lane's due looks, and in the
//        finisher at t_end;
//   void arm(int slot, const LaneState<D>& x, const Params& c, const Settlement& s)
//        after the look at load: the per-lane state its screen reads (main slots only);
//   template <class Tile> LookInt flag(const Tile& t, int i) const, or
//   template <class Tile> void screen(const Tile& t, LookInt* attention), or neither
//        vectorised over the main tile after each chunk: whether the lane in slot i needs a look.
//        A cheap predicate is a flag, evaluated inside the runner's own screen loop (the tile is
//        read once: the energy trap); a screen that updates state of its own makes a pass of
//        its own and ORs into attention[i] (the anchor test). Per-lane state is kept here,
//        structure of arrays, one entry per main slot, so that the loop vectorises like the
//        step (branch-free, no lane reads another). mapper_set.hpp says which does which;
//   void disarm(int slot)                 the lane settled (by any mapper), or its settlement was
//                                         refused: stop screening it;
//   bool refuses(const Settlement& s, const Params& c) const
//        whether a point another mapper settled on is known to be no attractor (the energy
//        trap knows V's saddles); the settlement is then undone;
//   void move(int from, int to)           a lane moves from main slot `from` to finisher slot
//                                         `to` (W + j): per-lane state that a look needs;
//   std::int64_t next_look(std::int64_t n) const
//        the step at which the mapper must next see a lane that is at step n (a sample it takes
//        on a schedule); INT64_MAX if none. Looks fall on multiples of the chunk.
// Slots 0 … W−1 are the main tile's, W … 2W−1 the finisher's (which is never screened).
//
// A lane's arithmetic stays its own: nothing a mapper keeps for one lane depends on another, so
// settlements are the same bits for any cut of the grid into blocks, ranks and threads.
#pragma once

#include <array>
#include <cstdint>

#include "engine/lane_clock.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// Where a lane settled: what every mapper writes (kept per block: settlement_records.hpp).
template <int N>
struct Settlement {
  bool settled = false;
  int period = 0;                // of the cycle (1: a fixed point)
  std::array<double, N> point{};  // q.., p..: the attractor's point, angles reduced
  double settle_time = 0.0;
};

}  // namespace cs
