// What a basin map says beyond its labels: the fraction of each basin, how mixed the basins are
// (basin entropy S_b and boundary basin entropy S_bb, Daza et al., Sci. Rep. 6, 31416, 2016),
// and how fast the uncertain set shrinks with the resolution (the uncertainty exponent α of
// McDonald, Grebogi, Ott & Yorke, Physica D 17, 125, 1985; boundary dimension D − α).
#pragma once

#include <cstdint>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "engine/wada_test.hpp"

namespace cs {

// A cell's basin label as the statistics see it: int32, whatever type the file stores it as.
using BasinLabel = std::int32_t;

struct BasinMapShape {
  std::vector<std::int64_t> dims;  // every grid axis, first slowest (row-major labels)
  int plane_axes = 0;              // the last 1 or 2 axes: initial conditions (0: none)
};

struct BasinStatistics {
  std::map<int, std::int64_t> cells;  // per label (0: undecided)
  std::int64_t points = 0;
  // Over boxes of box_cells^plane_axes cells of the plane (undecided counted as one more
  // outcome); NaN without a plane.
  int box_cells = 5;
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

BasinStatistics basin_statistics(const std::vector<BasinLabel>& labels, const BasinMapShape& shape);

// Fractions of each label per value of one axis (a continuation): fractions[value][label].
std::vector<std::map<int, double>> fractions_along(const std::vector<BasinLabel>& labels,
                                                   const BasinMapShape& shape, int axis);

// The parts the statistics read a band at a time share (engine/strip_statistics.hpp).
namespace basin_detail {
// The labels met in one box and how often: a few pairs, searched linearly (a std::map per box
// cost ~10 ms on a 512² map).
struct BoxCounts {
  std::vector<std::pair<int, int>> counts;
  void add(int label) {
    for (auto& [l, n] : counts)
      if (l == label) {
        ++n;
        return;
      }
    counts.emplace_back(label, 1);
  }
  double entropy(int total) const {
    double s = 0.0;
    for (const auto& [label, n] : counts) {
      const double p = static_cast<double>(n) / total;
      s -= p * std::log(p);
    }
    return s;
  }
};
// Least-squares slope of log f against log ε over the points with f > 0 (NaN under 3).
double log_log_slope(const std::vector<int>& eps, const std::vector<double>& f);
}  // namespace basin_detail

}  // namespace cs
