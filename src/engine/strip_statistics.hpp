// The statistics of a basin map (basin_statistics.hpp), read a band of rows at a time (a 1-D
// plane: a segment of its cells at a time), so that the process that computes them holds
// O(band), not O(map): rank 0 reads the labels back from the output file it has just written
// them to (parallel/basin_summary.cpp). The numbers do not depend on the band height, bit for
// bit: every count is an integer (cells per label, uncertain cells per ε, the Wada test's
// cells), and the one sum of doubles, the boxes' entropies, is added box by box in one order
// (slice, row of boxes, column) whatever the cut. A map held in memory is read through a reader
// over its array (tests/basin_maps.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "engine/basin_statistics.hpp"

namespace cs {

// Fills `out` with the labels of the flat grid points [begin, end) (row-major, first axis
// slowest).
using LabelReader = std::function<void(std::int64_t begin, std::int64_t end, BasinLabel* out)>;

struct MapStatistics {
  BasinStatistics whole;
  // Along options.fractions_axis (a continuation): fractions[value][label], each the label's
  // cells over the value's cells.
  std::vector<std::map<int, double>> fractions;
  std::vector<BasinStatistics> per_slice;  // per value of axis 0, if asked
  // The most labels its buffers held at once (their capacities), which the memory check's
  // count must cover (parallel/basin_summary.hpp, summary_bytes_on_rank0).
  std::int64_t most_cells_held = 0;
};

struct StripOptions {
  int fractions_axis = -1;  // fractions along this axis (-1: none)
  // The statistics of each slice along axis 0 on its own (a grid of that axis and the plane).
  bool per_slice = false;
  // Rows of a 2-D plane counted per band (0: about kStripCells cells).
  std::int64_t strip_rows = 0;
  // Cells of a 1-D plane counted per segment (0: kStripCells): a long 1-D plane is read a
  // segment at a time, not whole.
  std::int64_t line_cells = 0;
};

inline constexpr std::int64_t kStripCells = std::int64_t{1} << 20;

MapStatistics strip_statistics(const BasinMapShape& shape, const LabelReader& read,
                               const StripOptions& options = {});

}  // namespace cs
