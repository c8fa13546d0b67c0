// The statistics of a basin map (basin_statistics.hpp) read a band of rows at a time, so that
// the process that computes them holds O(band), not O(map): rank 0 reads the labels back from
// the output file it has just written them to (parallel/basin_summary.cpp). Same numbers, bit
// for bit, as basin_statistics and fractions_along on the whole map: every count is an integer
// (cells per label, uncertain cells per ε, the Wada test's cells), and the one sum of doubles,
// the boxes' entropies, is added box by box in the whole-map function's order (slice, row of
// boxes, column).
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
  BasinStatistics whole;                                   // basin_statistics(map)
  std::vector<std::map<int, double>> fractions;            // fractions_along(map, axis), axis >= 0
  std::vector<BasinStatistics> per_slice;                  // per value of axis 0, if asked
};

struct StripOptions {
  int fractions_axis = -1;  // fractions along this axis (-1: none)
  // basin_statistics of each slice along axis 0 on its own (a grid of that axis and the plane).
  bool per_slice = false;
  // Rows of the plane counted per band (0: about kStripCells cells). A 1-D plane is one row:
  // its band is the row, whatever its length.
  std::int64_t strip_rows = 0;
};

inline constexpr std::int64_t kStripCells = std::int64_t{1} << 20;

MapStatistics strip_statistics(const BasinMapShape& shape, const LabelReader& read,
                               const StripOptions& options = {});

}  // namespace cs
