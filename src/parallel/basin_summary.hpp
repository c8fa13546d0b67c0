// The basins of a finished run, across ranks: the attractor table (every rank), the final labels
// (each rank's blocks), and the statistics of the whole map (rank 0). See attractor_table.hpp
// and basin_statistics.hpp.
#pragma once

#include <mpi.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/attractor_analysis.hpp"
#include "engine/attractor_table.hpp"
#include "engine/basin_statistics.hpp"
#include "engine/strip_statistics.hpp"
#include "engine/run_plan.hpp"

namespace cs {

struct BasinSummary {
  std::vector<Attractor> table;
  // Along a continuation axis (the grid's first, a parameter): the attractors at each of its
  // values, labelled as in `table` (attractor_continuation.hpp); empty otherwise.
  std::vector<std::vector<Attractor>> along;
  // rank 0: each attractor's kind, λ₁, period in time and samples (attractor_analysis.hpp)
  std::vector<AttractorAnalysis> analysis;
  // The type of `basin` and `attractor_label`: int8 while the labels fit (the double well's
  // -1/+1 and every map of up to 127 attractors keep their files), int16, then int32, beyond.
  ElementType label_type = ElementType::int8;
  // What the labels mean: the scene's rule, or why it could not apply (the root attribute
  // `basin_labels`; `basin` then loses the rule's flags: output_assembly.cpp).
  Labelling labels;
  // Whether the energy trap decided basins, and if not why (the root attribute `energy_trap`).
  std::string energy_trap;
  // The unstable fixed points refused as attractors, per value of the continuation axis (one
  // list without one; empty where none was): AttractorTable::refused.
  std::vector<std::vector<Attractor>> refused;
  // Why lanes ended undecided, where the recurrence mapper runs or a fixed point was refused
  // (the root attribute `basin_undecided`; undecided_summary.hpp); empty otherwise.
  std::string undecided;
  BasinStatistics statistics;                    // rank 0, after add_statistics
  int continuation_axis = -1;                    // a parameter axis of the grid, if any
  std::vector<std::map<int, double>> continuation;  // rank 0: fractions per value of that axis
  std::vector<BasinStatistics> continuation_statistics;  // rank 0: per value, if it is axis 0
};

// Collective. Labels every block of `results` (they hold provisional labels until then); the
// statistics are left to add_statistics.
BasinSummary summarise_basins(const RunPlan& whole,
                              std::vector<std::unique_ptr<BlockResults>>& results, MPI_Comm comm);

// Rank 0, once `basin` is in the file: the statistics of the whole map (S_b, S_bb, α, the Wada
// test, the fractions along the continuation axis and per value), from its labels read a band
// of rows at a time (engine/strip_statistics.hpp).
void add_statistics(const RunPlan& whole, BasinSummary& summary, const LabelReader& read);

// Rank 0's memory for the statistics of the whole map, at the end: one band of the plane and
// its halos (add_statistics), not the map.
double summary_bytes_on_rank0(const RunPlan& whole);
// The same for a map of that shape (its labels' buffers: MapStatistics::most_cells_held).
double summary_bytes_on_rank0(const BasinMapShape& shape);

// The attractor table along a dimension `attractor`, the fractions along the continuation axis
// and the statistics as root attributes (INTERFACE.md).
void add_to_layout(const BasinSummary& basins, const RunPlan& plan, FileLayout& layout);

// The names add_to_layout will give the file's basin datasets, before any work is done (the
// same conditions as summarise_basins; values left empty).
void add_names_to_layout(const RunPlan& plan, FileLayout& layout);

// One line for the log: attractors, fractions, S_b, S_bb and the uncertainty exponent.
std::string describe(const BasinSummary& basins);

}  // namespace cs
