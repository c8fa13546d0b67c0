// What a basin map says beyond its labels: the fraction of each basin, how mixed the basins are
// (basin entropy S_b and boundary basin entropy S_bb, Daza et al., Sci. Rep. 6, 31416, 2016),
// and how fast the uncertain set shrinks with the resolution (the uncertainty exponent α of
// McDonald, Grebogi, Ott & Yorke, Physica D 17, 125, 1985; boundary dimension D − α). What
// the numbers are; engine/strip_statistics.hpp computes them.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "engine/wada_test.hpp"

namespace cs {

// A cell's basin label as the statistics see it: int32, whatever type the file stores it as.
using BasinLabel = std::int32_t;

struct BasinMapShape {
  std::vector<std::int64_t> dims;  // every grid axis, first slowest (row-major labels)
  int plane_axes = 0;              // the last 1 or 2 axes: initial conditions (0: none)
};

// Cells along each axis of a basin-entropy box (Daza et al. 2016 use 5): the box the
// statistics count (strip_statistics.cpp) and the `basin_entropy_box_cells` they report.
inline constexpr int kBasinEntropyBoxCells = 5;

struct BasinStatistics {
  std::map<int, std::int64_t> cells;  // per label (0: undecided)
  std::int64_t points = 0;
  // Over boxes of box_cells^plane_axes cells of the plane (undecided counted as one more
  // outcome); NaN without a plane.
  int box_cells = kBasinEntropyBoxCells;
  double basin_entropy = 0.0;
  double boundary_basin_entropy = 0.0;
  std::int64_t boxes = 0, boundary_boxes = 0;
  // f(ε): the fraction of cells whose neighbour ε cells away, along a plane axis, is in another
  // basin, for ε = 1, 2, 4, ...; α is the slope of log f against log ε (NaN if under 3 points).
  std::vector<int> epsilon_cells;
  std::vector<double> uncertain_fraction;
  double uncertainty_exponent = 0.0;
  double boundary_dimension = 0.0;
  WadaTest wada;  // over every 2-D plane with three basins or more (engine/wada_test.hpp)
};

}  // namespace cs
