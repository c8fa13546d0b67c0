// Why lanes ended undecided (basin 0), counted over every rank: the log's summary and the root
// attribute `basin_undecided` name each reason with its count and what to change (issue 23,
// item 4). Known where the recurrence mapper runs (RunPlan::map.undecided_reason).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "engine/run_plan.hpp"

namespace cs {

// Collective, from this rank's counts of undecided lanes per reason (kUndecidedReasons values:
// count_undecided, recurrence/lane_records.hpp). "" when every lane settled or the run does not
// record reasons.
std::string undecided_reasons(const RunPlan& whole, std::vector<std::int64_t> counts,
                              MPI_Comm comm);

}  // namespace cs
