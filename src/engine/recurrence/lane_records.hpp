// The recurrence mapper's per-point columns held compact once a block is saved in the journal:
// a record of RecurrenceSearch::kRecordWidth values (basin_cells) and a reason (undecided_reason)
// for every lane cost 88 bytes a point of each rank's blocks, kept to the end of the run for the
// attractor table and the labels. The table needs no more of them than each distinct record of
// a settled lane, with its settlement and reason (the lanes of one attractor mostly share one),
// and the summary of undecided lanes no more than a count per reason; the journal keeps every
// lane's values, so a block loaded on resume is compacted the same way.
//
// Compacted (BlockResults::basin_compacted, on a map where the mapper runs), a lane settled by
// the fixed-point mappers (no record, decided) keeps its provisional `basin` value, the number
// of its settlement record; the block's other settled lanes get one entry per distinct
// (settlement, record, reason), numbered after the settlement records in the order of their
// first lane: basin_records gains a copy of its settlement's (point.., period), so that
// settlement_of() reads it unchanged, basin_cells holds its record, and undecided_reason holds
// the count of the block's unsettled lanes per reason (kUndecidedReasons values) then each
// entry's reason. Every reader meets the same values in the same lane order as before: the
// table, the labels and the summary keep their bits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/results.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// Before the block's `basin` is compacted (basin_column.hpp, compact_basin), which calls it.
void compact_recurrence_columns(const RunPlan& plan, BlockResults& block);

// The record of a lane that settled (provisional `basin` value not 0); `lane` counts from the
// block's first point.
const double* recurrence_record_of(const RunPlan& plan, const BlockResults& block,
                                   std::size_t lane);

// Adds to `counts` (kUndecidedReasons) the block's undecided lanes (label 0) per reason, once it
// is labelled; `provisional` is its `basin` before it was labelled.
void count_undecided(const RunPlan& plan, const BlockResults& block,
                     const std::vector<double>& provisional, std::int64_t* counts);

}  // namespace cs
