// Attractors found by recurrences (period 0) in the run's table (attractor_table.cpp). A block's
// candidates are its lanes' distinct records (RecurrenceSearch::kRecordWidth: representative,
// located count, sketch; the lanes of one limit cycle mostly share one); all candidates of the
// run are joined by their cells (AttractorCells: equal or touching cells, transitively), which
// does not depend on the order of blocks; the attractors follow the table's other entries in
// order of their smallest cell. A lane's label is that of the attractor holding its
// representative cell.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/attractor_continuation.hpp"
#include "engine/attractor_table.hpp"
#include "engine/results.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// Appends the block's candidates found by recurrences to `records`, `width` values each:
// {the lane's grid index, value along `axis`, 0, the representative cell's centre (q.., p..),
// the record}.
void add_recurrence_candidates(const RunPlan& plan, const BlockResults& block,
                               std::vector<double>& records, std::size_t width,
                               const ContinuationAxis& axis);

// Appends the attractors of the records with period 0 (offsets into `records`) to `table`:
// period 0, the centre of their smallest cell as point, their cells' keys as cells.
void add_recurrence_attractors(const RunPlan& plan, const std::vector<double>& records,
                               const std::vector<std::size_t>& offsets,
                               std::vector<Attractor>& table);

// The label of the lane whose record is `record` (0 if no attractor holds it).
int recurrence_label(const std::vector<Attractor>& table, const double* record);

}  // namespace cs
