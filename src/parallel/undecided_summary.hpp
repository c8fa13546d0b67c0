// Why lanes ended undecided (basin 0), counted over every rank: the log's summary and the root
// attribute `basin_undecided` name each reason with its count and what to change (issue 23,
// item 4). Known where the recurrence mapper runs (RunPlan::map.undecided_reason).
#pragma once

#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

#include "engine/results.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// Collective; after the blocks are labelled. "" when every lane settled or the run does not
// record reasons.
std::string undecided_reasons(const RunPlan& whole,
                              const std::vector<std::unique_ptr<BlockResults>>& results,
                              MPI_Comm comm);

}  // namespace cs
