// The run's attractors, one table for the whole grid (INTERFACE.md, "Basins of any system").
//
// Each settled lane reports the point of its attractor (settlement_records.hpp). Within a block, lanes whose
// points lie within kLinkTolerances tolerances of a candidate's point (and have its period) join
// it; the candidates of all blocks are then merged the same way, in block order, and numbered in
// a sorted order by the scene's label rule. Blocks are a function of the spec alone (sweep.cpp), so the table and every
// label are the same bits for any number of ranks and threads; no rank's timing enters.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/fixed_point_exponent.hpp"
#include "engine/results.hpp"
#include "engine/run_plan.hpp"

namespace cs {

struct Attractor {
  int label = 0;
  int period = 1;             // of the stroboscopic map's cycle (1: a fixed point)
  std::vector<double> point;  // q.., p..; angles in [0, period)
  // Found by recurrences (period 0): the cells (keys) its lanes located, as far as their
  // records name them (recurrence_table.hpp); empty otherwise.
  std::vector<std::uint64_t> cells;
  // The grid index of a lane that settled on it (the first the table met): its parameters are
  // the attractor's (attractor_analysis.cpp).
  std::int64_t source = -1;
  // A fixed point's Jacobian at its point, evaluated once where the table was merged with a
  // Jacobian (merge_candidates): its λ₁, which refuses an unstable one, and its description read
  // it (attractor_analysis.hpp, linearisation_of). Empty otherwise: they evaluate it then.
  std::optional<FixedPointLinearisation> linearisation{};
};

// Lanes of one attractor sit within about a tolerance of it; attractors must be further apart
// than this many tolerances to be told apart.
inline constexpr double kLinkTolerances = 4.0;
// Labels are int32 here (int8, int16 or int32 in the file: BasinSummary::label_type), and a
// table holds at most one attractor per grid point: RunPlan refuses, before any work, a basin
// map of more points than labels.
inline constexpr std::int64_t kMaxAttractors = 2147483647;

// The block's candidate attractors, flat: per candidate {grid index of its first lane, value,
// period, point..}, `value` the index along the continuation axis of its lanes
// (attractor_continuation.hpp; 0 without one): a block that spans two values gives candidates
// for each. In grid order, so sorting by the first value keeps block order.
inline constexpr std::size_t kCandidateHead = 3;  // first lane, value, period
std::vector<double> block_candidates(const RunPlan& plan, const BlockResults& block);

// How the table's labels were chosen (label_rule.hpp).
struct Labelling {
  bool by_rule = true;      // false: the scene's rule fell back to numbering
  std::string description;  // for the file (basin_labels) and the log; empty for `numbered`
};

// The table, sorted by (period, point), and how its labels were chosen. Along a continuation
// axis: one attractor per branch (its point where it was first found), and `along[k]` the
// attractors found at the axis' k-th value, each with its branch's label.
//
// `refused`: the unstable fixed points met (merge_candidates), per value of the continuation
// axis (one list without one), each with label 0; empty where none was refused.
struct AttractorTable {
  std::vector<Attractor> attractors;
  Labelling labels;
  std::vector<std::vector<Attractor>> along;  // empty without a continuation axis
  std::vector<std::vector<Attractor>> refused;
};

// The table from every block's candidates (any order of blocks: they are sorted first),
// labelled by the scene's rule (label_rule.hpp); continued along the grid's first axis when
// it is a parameter (attractor_continuation.hpp). With `fixed` (the Jacobian at a fixed point:
// fixed_point_exponent.hpp), each fixed point's linearisation is evaluated once and kept in it,
// and an unstable one (attractor_analysis.hpp, unstable_fixed_point) is no attractor: it leaves
// the value's table for `refused` before the tables are sorted, continued and labelled, so the
// others are labelled as if it had never been found (renumbered where numbered; the scene's
// rule may apply where the point alone stopped it: a saddle at q1 = 0).
AttractorTable merge_candidates(const RunPlan& plan, const std::vector<double>& records,
                                FixedPointExponentFn fixed = nullptr);

// Replaces the provisional labels of a block (1: settled) by the table's: by `along`'s table
// of the lane's value where there is a continuation axis. A lane nearer a refused point
// (`refused`, as AttractorTable's) than any attractor of its period is labelled 0; returns how
// many were.
std::int64_t label_block(const RunPlan& plan, const std::vector<Attractor>& table,
                         BlockResults& block, const std::vector<std::vector<Attractor>>& along = {},
                         const std::vector<std::vector<Attractor>>& refused = {});

}  // namespace cs
