// The statistics of a basin map read a band of rows at a time (engine/strip_statistics.hpp)
// against the whole-map functions (basin_statistics, fractions_along), bit for bit: several
// basins and undecided cells, 1-D and 2-D planes, slices and a continuation axis, bands that do
// not divide the plane, a band of one row and bands thinner than the boxes, the largest ε and
// the Wada test's halo, and a map whose boundary is Wada.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstring>
#include <numbers>
#include <random>

#include "engine/basin_statistics.hpp"
#include "engine/strip_statistics.hpp"

namespace cs {
namespace {

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

void expect_same(const BasinStatistics& a, const BasinStatistics& b) {
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_EQ(a.points, b.points);
  EXPECT_TRUE(same_bits(a.basin_entropy, b.basin_entropy)) << a.basin_entropy << " " << b.basin_entropy;
  EXPECT_TRUE(same_bits(a.boundary_basin_entropy, b.boundary_basin_entropy));
  EXPECT_EQ(a.boxes, b.boxes);
  EXPECT_EQ(a.boundary_boxes, b.boundary_boxes);
  EXPECT_EQ(a.epsilon_cells, b.epsilon_cells);
  ASSERT_EQ(a.uncertain_fraction.size(), b.uncertain_fraction.size());
  for (std::size_t k = 0; k < a.uncertain_fraction.size(); ++k)
    EXPECT_TRUE(same_bits(a.uncertain_fraction[k], b.uncertain_fraction[k])) << k;
  EXPECT_TRUE(same_bits(a.uncertainty_exponent, b.uncertainty_exponent));
  EXPECT_TRUE(same_bits(a.boundary_dimension, b.boundary_dimension));
  EXPECT_EQ(a.wada.boundary_cells, b.wada.boundary_cells);
  EXPECT_EQ(a.wada.touching_all, b.wada.touching_all);
  EXPECT_EQ(a.wada.covered, b.wada.covered);
  EXPECT_EQ(a.wada.planes_tested, b.wada.planes_tested);
  EXPECT_EQ(a.wada.planes_too_many, b.wada.planes_too_many);
  EXPECT_EQ(a.wada.verdict(), b.wada.verdict());
}

LabelReader reader_of(const std::vector<BasinLabel>& labels, std::int64_t* reads = nullptr) {
  return [&labels, reads](std::int64_t begin, std::int64_t end, BasinLabel* out) {
    ASSERT_LE(0, begin);
    ASSERT_LE(begin, end);
    ASSERT_LE(end, static_cast<std::int64_t>(labels.size()));
    std::memcpy(out, labels.data() + begin, static_cast<std::size_t>(end - begin) * sizeof(BasinLabel));
    if (reads) *reads = std::max(*reads, end - begin);
  };
}

// Smooth regions of `basins` labels, a fractal-looking seam and undecided specks: boxes and
// every ε see boundaries, and a few cells are 0.
std::vector<BasinLabel> mixed_map(std::int64_t cells, std::int64_t columns, int basins, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<BasinLabel> labels(static_cast<std::size_t>(cells));
  for (std::int64_t i = 0; i < cells; ++i) {
    const double x = static_cast<double>(i % columns) / static_cast<double>(columns);
    const double y = static_cast<double>(i / columns) / 17.0;
    const double phase = std::sin(9.0 * x + 2.0 * std::sin(31.0 * y) + std::cos(47.0 * x * y));
    labels[static_cast<std::size_t>(i)] =
        static_cast<BasinLabel>(std::floor((phase + 1.0) / 2.0 * basins * 0.999)) - 1;
    if (random() % 23 == 0) labels[static_cast<std::size_t>(i)] = 0;
    if (random() % 41 == 0) labels[static_cast<std::size_t>(i)] = static_cast<BasinLabel>(random() % basins) + 1;
  }
  return labels;
}

void expect_same_for_strips(const std::vector<BasinLabel>& labels, const BasinMapShape& shape,
                            int axis = -1) {
  const BasinStatistics whole = basin_statistics(labels, shape);
  const bool per_slice = axis == 0 && shape.plane_axes > 0 &&
                         shape.dims.size() == static_cast<std::size_t>(shape.plane_axes) + 1;
  for (std::int64_t strip : {1, 2, 3, 4, 7, 13, 64, 1000}) {
    SCOPED_TRACE(strip);
    std::int64_t largest_read = 0;
    const MapStatistics s = strip_statistics(shape, reader_of(labels, &largest_read),
                                             {axis, per_slice, strip});
    expect_same(s.whole, whole);
    if (axis >= 0) {
      const auto fractions = fractions_along(labels, shape, axis);
      ASSERT_EQ(s.fractions.size(), fractions.size());
      for (std::size_t v = 0; v < fractions.size(); ++v) {
        ASSERT_EQ(s.fractions[v].size(), fractions[v].size());
        for (const auto& [label, f] : fractions[v]) EXPECT_TRUE(same_bits(s.fractions[v].at(label), f));
      }
    }
    if (per_slice) {
      BasinMapShape slice = shape;
      slice.dims.erase(slice.dims.begin());
      const auto cells = static_cast<std::ptrdiff_t>(labels.size()) / shape.dims[0];
      ASSERT_EQ(s.per_slice.size(), static_cast<std::size_t>(shape.dims[0]));
      for (std::int64_t v = 0; v < shape.dims[0]; ++v)
        expect_same(s.per_slice[static_cast<std::size_t>(v)],
                    basin_statistics(std::vector<BasinLabel>(labels.begin() + v * cells,
                                                             labels.begin() + (v + 1) * cells),
                                     slice));
    }
    // O(band): with a thin band no read spans the plane (1-D planes aside: a row each).
    if (shape.plane_axes == 2 && strip < 64) {
      const std::int64_t row = shape.dims.back();
      EXPECT_LT(largest_read, 40 * row);
    }
  }
}

TEST(StripStatistics, TwoDimensionalPlaneWithUndecidedCells) {
  // 97 rows: no band height above divides it; ε reaches 8 rows, beyond every small band.
  const std::vector<BasinLabel> labels = mixed_map(97 * 83, 83, 3, 1);
  expect_same_for_strips(labels, {{97, 83}, 2});
}

TEST(StripStatistics, ManyBasinsAndWideEpsilon) {
  const std::vector<BasinLabel> labels = mixed_map(160 * 131, 131, 6, 2);
  const BasinStatistics whole = basin_statistics(labels, {{160, 131}, 2});
  ASSERT_GE(whole.epsilon_cells.size(), 4u);  // ε = 1 … 16: bands far thinner than 2ε
  ASSERT_GT(whole.wada.boundary_cells, 0);     // six basins: the Wada test runs
  expect_same_for_strips(labels, {{160, 131}, 2});
}

TEST(StripStatistics, OneDimensionalPlaneAndSlices) {
  const std::vector<BasinLabel> labels = mixed_map(7 * 5 * 203, 203, 4, 3);
  expect_same_for_strips(labels, {{7, 5, 203}, 1});
  expect_same_for_strips(labels, {{7, 5, 203}, 1}, 1);  // fractions along the second axis
}

TEST(StripStatistics, ContinuationAxisPerSlice) {
  const std::vector<BasinLabel> labels = mixed_map(5 * 41 * 37, 37, 3, 4);
  expect_same_for_strips(labels, {{5, 41, 37}, 2}, 0);
}

TEST(StripStatistics, NoPlane) {
  const std::vector<BasinLabel> labels = mixed_map(3 * 11, 11, 3, 5);
  expect_same_for_strips(labels, {{3, 11}, 0}, 0);
}

// Newton's basins of z³ = 1, a Wada boundary (tests/test_wada.cpp): the verdict and every count
// of the merging method from bands of any height.
TEST(StripStatistics, WadaBoundary) {
  const int n = 96;
  std::vector<BasinLabel> labels(static_cast<std::size_t>(n) * n, 0);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      std::complex<double> z(-2.0 + 4.0 * (c + 0.5) / n, -2.0 + 4.0 * (r + 0.5) / n);
      for (int k = 0; k < 60; ++k) z -= (z * z * z - 1.0) / (3.0 * z * z);
      for (int j = 0; j < 3; ++j)
        if (std::abs(z - std::polar(1.0, 2.0 * std::numbers::pi * j / 3.0)) < 1e-6)
          labels[static_cast<std::size_t>(r) * n + c] = j + 1;
    }
  const BasinStatistics whole = basin_statistics(labels, {{n, n}, 2});
  ASSERT_EQ(whole.wada.planes_tested, 1);
  ASSERT_GT(whole.wada.boundary_cells, 100);
  expect_same_for_strips(labels, {{n, n}, 2});
  expect_same_for_strips(labels, {{1, n, n}, 2}, 0);
}

}  // namespace
}  // namespace cs
