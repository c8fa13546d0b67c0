// Why lanes ended undecided (basin 0), counted over every rank: the log's summary and the root
// attribute `basin_undecided` name each reason with its count and what to change (issue 23,
// item 4). Known where the recurrence mapper runs (RunPlan::map.undecided_reason), and for the
// lanes on an unstable fixed point wherever one was refused.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "engine/run_plan.hpp"

namespace cs {

// The lanes that settled on a fixed point refused as unstable (attractor_table.hpp): this rank's
// count, and the points (the same text on every rank).
struct RefusedLanes {
  std::int64_t lanes = 0;
  std::string points;
};

// Collective, from this rank's counts of undecided lanes per reason (kUndecidedReasons values:
// count_undecided, recurrence/lane_records.hpp; zeros where the run records no reasons) and of
// its lanes on refused points. "" when every lane settled on an attractor, or the run records no
// reasons and refused none.
std::string undecided_reasons(const RunPlan& whole, std::vector<std::int64_t> counts,
                              RefusedLanes refused, MPI_Comm comm);

}  // namespace cs
