// The statistics of a basin map read a band of rows at a time (engine/strip_statistics.hpp): the
// numbers of a straight boundary in closed form, and every statistic the same, bit for bit,
// whatever the band height, against one band holding the whole plane: several basins and
// undecided cells, 1-D and 2-D planes, slices and a continuation axis (its fractions against
// a plain count), bands that do not divide the plane, a band of one row and bands thinner than
// the boxes, the largest ε and the Wada test's halo, and a map whose boundary is Wada
// (test_wada.cpp checks the Wada test's verdicts on maps whose answer is known).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "basin_maps.hpp"
#include "engine/strip_statistics.hpp"
#include "parallel/basin_summary.hpp"

namespace cs {
namespace {

using test::reader_of;

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

// The fractions along `axis` by a plain count: fractions[value][label].
std::vector<std::map<int, double>> counted_fractions(const std::vector<BasinLabel>& labels,
                                                     const BasinMapShape& shape, int axis) {
  std::int64_t stride = 1;
  for (std::size_t a = static_cast<std::size_t>(axis) + 1; a < shape.dims.size(); ++a) stride *= shape.dims[a];
  const std::int64_t values = shape.dims[static_cast<std::size_t>(axis)];
  std::vector<std::map<int, std::int64_t>> counts(static_cast<std::size_t>(values));
  for (std::size_t i = 0; i < labels.size(); ++i)
    ++counts[static_cast<std::size_t>((static_cast<std::int64_t>(i) / stride) % values)][labels[i]];
  std::vector<std::map<int, double>> fractions(counts.size());
  for (std::size_t v = 0; v < counts.size(); ++v) {
    std::int64_t total = 0;
    for (const auto& [label, n] : counts[v]) total += n;
    for (const auto& [label, n] : counts[v])
      fractions[v][label] = static_cast<double>(n) / static_cast<double>(total);
  }
  return fractions;
}

void expect_same_fractions(const std::vector<std::map<int, double>>& a,
                           const std::vector<std::map<int, double>>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t v = 0; v < a.size(); ++v) {
    ASSERT_EQ(a[v].size(), b[v].size()) << v;
    for (const auto& [label, f] : b[v]) EXPECT_TRUE(same_bits(a[v].at(label), f)) << v << " " << label;
  }
}

std::int64_t plane_rows(const BasinMapShape& shape) {
  return shape.plane_axes == 2 ? shape.dims[shape.dims.size() - 2] : 1;
}

void expect_same_for_strips(const std::vector<BasinLabel>& labels, const BasinMapShape& shape,
                            int axis = -1) {
  const bool per_slice = axis == 0 && shape.plane_axes > 0 &&
                         shape.dims.size() == static_cast<std::size_t>(shape.plane_axes) + 1;
  const std::int64_t rows = plane_rows(shape);
  // The reference: one band holding the whole plane, read at once (no halo, nothing read again).
  std::int64_t whole_read = 0;
  const MapStatistics one = strip_statistics(shape, reader_of(labels, &whole_read), {axis, per_slice, rows});
  if (shape.plane_axes > 0) {
    ASSERT_EQ(whole_read, rows * shape.dims.back());
  }
  if (axis >= 0) expect_same_fractions(one.fractions, counted_fractions(labels, shape, axis));
  if (per_slice) {
    // Each slice's statistics, as those of a map of that slice alone.
    BasinMapShape slice = shape;
    slice.dims.erase(slice.dims.begin());
    const auto cells = static_cast<std::ptrdiff_t>(labels.size()) / shape.dims[0];
    ASSERT_EQ(one.per_slice.size(), static_cast<std::size_t>(shape.dims[0]));
    for (std::int64_t v = 0; v < shape.dims[0]; ++v) {
      const std::vector<BasinLabel> alone(labels.begin() + v * cells, labels.begin() + (v + 1) * cells);
      expect_same(one.per_slice[static_cast<std::size_t>(v)],
                  strip_statistics(slice, reader_of(alone), {-1, false, rows}).whole);
    }
  }
  for (std::int64_t strip : {1, 2, 3, 4, 7, 13, 64, 1000}) {
    SCOPED_TRACE(strip);
    std::int64_t largest_read = 0;
    const MapStatistics s = strip_statistics(shape, reader_of(labels, &largest_read),
                                             {axis, per_slice, strip, strip});
    expect_same(s.whole, one.whole);
    if (axis >= 0) expect_same_fractions(s.fractions, one.fractions);
    ASSERT_EQ(s.per_slice.size(), one.per_slice.size());
    for (std::size_t v = 0; v < s.per_slice.size(); ++v) expect_same(s.per_slice[v], one.per_slice[v]);
    // O(band): with a thin band no read spans the plane. A 1-D plane's segment is read with a
    // segment's reach on either side and the 4 cells its last box reaches beyond it.
    if (shape.plane_axes == 2 && strip < 64) {
      const std::int64_t row = shape.dims.back();
      EXPECT_LT(largest_read, 40 * row);
    }
    if (shape.plane_axes == 1) {
      EXPECT_LE(largest_read, std::min(3 * strip + 4, shape.dims.back()));
    }
  }
}

// Two basins split by a straight vertical line between columns C/2 − 1 and C/2, C/2 = 2 mod 5:
// in every row of 5 × 5 boxes one box straddles it, 2 columns of one basin and 3 of the other,
// so S_bb = h = −(0.4 ln 0.4 + 0.6 ln 0.6) and S_b = h / (boxes per row). A cell is uncertain at
// ε when the line runs within ε of it: 2ε of the C − 2ε columns tested, f(ε) = 2ε / (C − 2ε),
// whose log-log slope lies between 1 and 1 + 2ε/(C − 2ε) at the largest ε (the slope of
// −ln(C − 2ε) against ln ε is 2ε/(C − 2ε), growing with ε): α → 1, a boundary of dimension 1.
TEST(StripStatistics, StraightBoundaryInClosedForm) {
  const std::int64_t rows = 40, columns = 64;
  std::vector<BasinLabel> labels(static_cast<std::size_t>(rows * columns));
  for (std::int64_t i = 0; i < rows * columns; ++i)
    labels[static_cast<std::size_t>(i)] = i % columns < columns / 2 ? 1 : 2;
  const BasinMapShape shape{{rows, columns}, 2};
  const BasinStatistics s = test::statistics_of(labels, shape);
  EXPECT_EQ(s.points, rows * columns);
  EXPECT_EQ(s.cells, (std::map<int, std::int64_t>{{1, rows * columns / 2}, {2, rows * columns / 2}}));
  const double h = -(0.4 * std::log(0.4) + 0.6 * std::log(0.6));
  EXPECT_EQ(s.boxes, (rows / 5) * (columns / 5));
  EXPECT_EQ(s.boundary_boxes, rows / 5);
  EXPECT_NEAR(s.boundary_basin_entropy, h, 1e-15);
  EXPECT_NEAR(s.basin_entropy, h / static_cast<double>(columns / 5), 1e-15);
  EXPECT_EQ(s.epsilon_cells, (std::vector<int>{1, 2, 4}));  // 8ε within the 40 rows
  ASSERT_EQ(s.uncertain_fraction.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const double eps = s.epsilon_cells[k];
    EXPECT_DOUBLE_EQ(s.uncertain_fraction[k], 2.0 * eps / (columns - 2.0 * eps)) << eps;
  }
  EXPECT_GT(s.uncertainty_exponent, 1.0);
  EXPECT_LT(s.uncertainty_exponent, 1.0 + 8.0 / (columns - 8.0));
  EXPECT_DOUBLE_EQ(s.boundary_dimension, 2.0 - s.uncertainty_exponent);
  EXPECT_FALSE(s.wada.applies());  // two basins
  expect_same_for_strips(labels, shape);
}

// The same line on a 1-D plane of C cells, C/2 = 2 mod 5: one box of 5 cells straddles it (2
// and 3 cells), S_bb = h and S_b = h / (C/5); ε cells on each side of it are uncertain at ε,
// f(ε) = 2ε / (C − 2ε). The row is read in segments, some far shorter than the largest ε (64):
// each read once with its reach (a segment, at most the largest ε) on either side, the ε beyond
// that reach read again.
TEST(StripStatistics, StraightBoundaryOnALineInClosedForm) {
  const std::int64_t columns = 1004;
  std::vector<BasinLabel> labels(static_cast<std::size_t>(columns));
  for (std::int64_t c = 0; c < columns; ++c) labels[static_cast<std::size_t>(c)] = c < columns / 2 ? 1 : 2;
  const BasinMapShape shape{{columns}, 1};
  const double h = -(0.4 * std::log(0.4) + 0.6 * std::log(0.6));
  for (std::int64_t segment : {0, 1, 6, 333}) {
    SCOPED_TRACE(segment);
    std::int64_t largest_read = 0, total_read = 0;
    const BasinStatistics s =
        strip_statistics(shape, reader_of(labels, &largest_read, &total_read), {-1, false, 0, segment}).whole;
    const std::int64_t cut = segment == 0 ? columns : segment, reach = std::min<std::int64_t>(cut, 64);
    const std::int64_t segments = (columns + cut - 1) / cut;
    EXPECT_EQ(largest_read, std::min(columns, cut + reach + std::max<std::int64_t>(reach, 4)));
    // Each segment once with its reach; an ε beyond the reach (ε > segment) twice more.
    std::int64_t beyond = 0;
    for (std::int64_t eps = 1; 8 * eps <= columns; eps *= 2)
      if (eps > reach) beyond += 2 * (columns - 2 * eps);
    EXPECT_LE(total_read, columns + segments * (2 * reach + 4) + beyond);
    if (segment == 333) {
      EXPECT_LT(total_read, 2 * columns);  // the largest ε within reach
    }
    EXPECT_EQ(s.cells, (std::map<int, std::int64_t>{{1, columns / 2}, {2, columns / 2}}));
    EXPECT_EQ(s.boxes, columns / 5);
    EXPECT_EQ(s.boundary_boxes, 1);
    EXPECT_NEAR(s.boundary_basin_entropy, h, 1e-15);
    EXPECT_NEAR(s.basin_entropy, h / static_cast<double>(columns / 5), 1e-15);
    EXPECT_EQ(s.epsilon_cells, (std::vector<int>{1, 2, 4, 8, 16, 32, 64}));  // 8ε within the row
    ASSERT_EQ(s.uncertain_fraction.size(), s.epsilon_cells.size());
    for (std::size_t k = 0; k < s.epsilon_cells.size(); ++k) {
      const double eps = s.epsilon_cells[k];
      EXPECT_DOUBLE_EQ(s.uncertain_fraction[k], 2.0 * eps / (columns - 2.0 * eps)) << eps;
    }
    EXPECT_GT(s.uncertainty_exponent, 1.0);  // as on the plane: α → 1, a boundary of dimension 0
    EXPECT_LT(s.uncertainty_exponent, 1.0 + 128.0 / (columns - 128.0));
    EXPECT_DOUBLE_EQ(s.boundary_dimension, 1.0 - s.uncertainty_exponent);
  }
  expect_same_for_strips(labels, shape);
}

// 1-D planes against the definitions, computed directly over whole rows (slice by slice, box by
// box in order along the row, so the sums keep their bits): rows shorter than a box and than
// 8 cells (no box, no ε), rows that are no multiple of 5, a continuation axis per slice, and a
// row longer than the default segment of 2^20 cells.
struct LineReference {
  std::map<int, std::int64_t> cells;
  std::int64_t boxes = 0, boundary_boxes = 0;
  double sum = 0.0, boundary_sum = 0.0;
  std::vector<std::int64_t> tested, uncertain;
};

LineReference line_reference(const std::vector<BasinLabel>& labels, std::int64_t slices, std::int64_t columns) {
  LineReference r;
  for (std::int64_t e = 1; 8 * e <= columns; e *= 2) r.tested.push_back(0), r.uncertain.push_back(0);
  for (std::int64_t s = 0; s < slices; ++s) {
    const BasinLabel* row = labels.data() + s * columns;
    for (std::int64_t c = 0; c < columns; ++c) ++r.cells[row[c]];
    for (std::int64_t c0 = 0; c0 + 5 <= columns; c0 += 5) {
      std::map<int, int> in_box;
      for (std::int64_t c = c0; c < c0 + 5; ++c) ++in_box[row[c]];
      double entropy = 0.0;  // in the order the labels were met, as BoxCounts adds them
      std::vector<int> met;
      for (std::int64_t c = c0; c < c0 + 5; ++c)
        if (std::find(met.begin(), met.end(), row[c]) == met.end()) met.push_back(row[c]);
      for (int label : met) entropy -= in_box[label] / 5.0 * std::log(in_box[label] / 5.0);
      r.sum += entropy, ++r.boxes;
      if (met.size() > 1) r.boundary_sum += entropy, ++r.boundary_boxes;
    }
    std::size_t k = 0;
    for (std::int64_t e = 1; 8 * e <= columns; e *= 2, ++k)
      for (std::int64_t c = e; c < columns - e; ++c) {
        ++r.tested[k];
        r.uncertain[k] += row[c - e] != row[c] || row[c + e] != row[c];
      }
  }
  return r;
}

void expect_line_reference(const std::vector<BasinLabel>& labels, std::int64_t slices, std::int64_t columns,
                           std::int64_t segment) {
  SCOPED_TRACE(testing::Message() << slices << " x " << columns << ", segment " << segment);
  const LineReference r = line_reference(labels, slices, columns);
  const BasinStatistics s =
      strip_statistics({{slices, columns}, 1}, reader_of(labels), {-1, false, 0, segment}).whole;
  EXPECT_EQ(s.cells, r.cells);
  EXPECT_EQ(s.points, slices * columns);
  EXPECT_EQ(s.boxes, r.boxes);
  EXPECT_EQ(s.boundary_boxes, r.boundary_boxes);
  if (r.boxes == 0) {
    EXPECT_TRUE(std::isnan(s.basin_entropy));
  } else {
    EXPECT_TRUE(same_bits(s.basin_entropy, r.sum / static_cast<double>(r.boxes)));
  }
  if (r.boundary_boxes > 0) {
    EXPECT_TRUE(same_bits(s.boundary_basin_entropy, r.boundary_sum / static_cast<double>(r.boundary_boxes)));
  }
  ASSERT_EQ(s.uncertain_fraction.size(), r.tested.size());
  for (std::size_t k = 0; k < r.tested.size(); ++k)
    EXPECT_TRUE(same_bits(s.uncertain_fraction[k],
                          static_cast<double>(r.uncertain[k]) / static_cast<double>(r.tested[k])))
        << k;
}

TEST(StripStatistics, OneDimensionalPlaneAgainstTheDefinitions) {
  for (std::int64_t columns : {1, 3, 4, 5, 7, 8, 9, 16, 17, 203, 1023}) {
    const std::vector<BasinLabel> labels = mixed_map(3 * columns, columns, 4, 7);
    for (std::int64_t segment : {0, 1, 2, 5, 7, 64}) expect_line_reference(labels, 3, columns, segment);
  }
  // The production layout of a continuation along a line: the parameter first, per slice.
  expect_same_for_strips(mixed_map(7 * 1015, 1015, 3, 8), {{7, 1015}, 1}, 0);
  // Longer than the default segment (2^20 cells): the default path cuts it.
  const std::int64_t long_row = (std::int64_t{1} << 20) + 13;
  const std::vector<BasinLabel> labels = mixed_map(long_row, long_row, 3, 9);
  expect_line_reference(labels, 1, long_row, 0);
}

// What the statistics hold at once (their buffers' capacities) is what the memory check counts
// for them on rank 0 (summary_bytes_on_rank0), and no more than the reads need. A 1-D plane:
// a segment of 2^20 cells with a reach of the largest ε (8ε within the row) on either side; a
// segment shorter than ε reads that ε's neighbours into two buffers of a segment each. A 2-D
// plane: a band and its halos.
TEST(StripStatistics, HoldsWhatTheMemoryCheckCounts) {
  const std::int64_t segment = std::int64_t{1} << 20;
  struct Line {
    std::int64_t columns, largest_eps, most;
  };
  for (const Line& line : {Line{1023, 64, 1023},  // the whole row, shorter than a segment
                           Line{segment + 13, segment / 8, segment + 13},  // the reach passes its end
                           Line{3 * segment + 7, segment / 4, segment + 2 * (segment / 4)}}) {
    SCOPED_TRACE(line.columns);
    ASSERT_LE(8 * line.largest_eps, line.columns);
    ASSERT_GT(16 * line.largest_eps, line.columns);
    const BasinMapShape shape{{line.columns}, 1};
    const MapStatistics s = strip_statistics(shape, reader_of(mixed_map(line.columns, line.columns, 3, 9)));
    EXPECT_EQ(s.most_cells_held, line.most);
    EXPECT_LE(static_cast<double>(s.most_cells_held) * sizeof(BasinLabel), summary_bytes_on_rank0(shape));
  }
  // Segments of 6 cells on a row of 1004: a window of 6 + 2·6, and ε up to 64 read beside it.
  const std::vector<BasinLabel> row = mixed_map(1004, 1004, 3, 4);
  EXPECT_EQ(strip_statistics({{1004}, 1}, reader_of(row), {-1, false, 0, 6}).most_cells_held, 5 * 6);
  // A 2-D plane within one band: held whole, once.
  const BasinMapShape plane{{97, 83}, 2};
  const MapStatistics p = strip_statistics(plane, reader_of(mixed_map(97 * 83, 83, 3, 1)));
  EXPECT_EQ(p.most_cells_held, 97 * 83);
  EXPECT_LE(static_cast<double>(p.most_cells_held) * sizeof(BasinLabel), summary_bytes_on_rank0(plane));
  // Bands of 10 rows of a 300 × 40 plane (ε = 1, 2, 4): the band and the 4 rows below it its
  // boxes reach, which also hold the rows ε below; the rows ε above it, read (10 rows); then
  // the Wada pass's band, 10 rows and their halos, held alone.
  const MapStatistics b = strip_statistics({{300, 40}, 2}, reader_of(mixed_map(300 * 40, 40, 3, 2)),
                                           {-1, false, 10, 0});
  EXPECT_EQ(b.most_cells_held,
            std::max<std::int64_t>((10 + 4 + 10) * 40, std::min<std::int64_t>(300, 10 + 2 * wada_detail::kHalo) * 40));
}

// 2-D planes against the definitions, computed directly over whole planes: every box of 5 × 5
// cells (rows of boxes, then columns; within a box row by row, as BoxCounts meets the labels),
// and for each ε every cell with all four neighbours ε away inside the plane, uncertain if one
// of them differs. Planes whose sides are multiples of 5 (the last row and column of boxes),
// boundaries across and along the rows, and the least-squares exponent of f(ε) (NaN with fewer
// than 3 values of ε). Band heights from 1 row to the whole plane.
struct PlaneReference {
  std::map<int, std::int64_t> cells;
  std::int64_t boxes = 0, boundary_boxes = 0;
  double sum = 0.0, boundary_sum = 0.0;
  std::vector<int> eps;
  std::vector<std::int64_t> tested, uncertain;
};

PlaneReference plane_reference(const std::vector<BasinLabel>& labels, std::int64_t slices, std::int64_t rows,
                               std::int64_t columns) {
  PlaneReference r;
  for (std::int64_t e = 1; 8 * e <= std::min(rows, columns); e *= 2)
    r.eps.push_back(static_cast<int>(e)), r.tested.push_back(0), r.uncertain.push_back(0);
  for (std::int64_t s = 0; s < slices; ++s) {
    const BasinLabel* plane = labels.data() + s * rows * columns;
    const auto at = [&](std::int64_t row, std::int64_t column) { return plane[row * columns + column]; };
    for (std::int64_t i = 0; i < rows * columns; ++i) ++r.cells[plane[i]];
    for (std::int64_t r0 = 0; r0 + 5 <= rows; r0 += 5)
      for (std::int64_t c0 = 0; c0 + 5 <= columns; c0 += 5) {
        std::vector<std::pair<int, int>> met;  // label, count: in the order met
        for (std::int64_t row = r0; row < r0 + 5; ++row)
          for (std::int64_t column = c0; column < c0 + 5; ++column) {
            auto it = std::find_if(met.begin(), met.end(), [&](const auto& m) { return m.first == at(row, column); });
            if (it == met.end()) met.emplace_back(at(row, column), 1);
            else ++it->second;
          }
        double entropy = 0.0;
        for (const auto& [label, n] : met) entropy -= n / 25.0 * std::log(n / 25.0);
        r.sum += entropy, ++r.boxes;
        if (met.size() > 1) r.boundary_sum += entropy, ++r.boundary_boxes;
      }
    for (std::size_t k = 0; k < r.eps.size(); ++k) {
      const std::int64_t e = r.eps[k];
      for (std::int64_t row = e; row < rows - e; ++row)
        for (std::int64_t column = e; column < columns - e; ++column) {
          const BasinLabel here = at(row, column);
          ++r.tested[k];
          r.uncertain[k] += at(row - e, column) != here || at(row + e, column) != here ||
                            at(row, column - e) != here || at(row, column + e) != here;
        }
    }
  }
  return r;
}

void expect_plane_reference(const std::vector<BasinLabel>& labels, std::int64_t slices, std::int64_t rows,
                            std::int64_t columns) {
  const PlaneReference r = plane_reference(labels, slices, rows, columns);
  std::vector<double> x, y;  // log ε, log f(ε) where f > 0
  for (std::size_t k = 0; k < r.eps.size(); ++k)
    if (r.uncertain[k] > 0)
      x.push_back(std::log(r.eps[k])),
          y.push_back(std::log(static_cast<double>(r.uncertain[k]) / static_cast<double>(r.tested[k])));
  double slope = NAN;
  if (x.size() >= 3) {
    const double n = static_cast<double>(x.size());
    double mx = 0.0, my = 0.0, sxy = 0.0, sxx = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) mx += x[k] / n, my += y[k] / n;
    for (std::size_t k = 0; k < x.size(); ++k) sxy += (x[k] - mx) * (y[k] - my), sxx += (x[k] - mx) * (x[k] - mx);
    slope = sxy / sxx;
  }
  const BasinMapShape shape = slices == 1 ? BasinMapShape{{rows, columns}, 2} : BasinMapShape{{slices, rows, columns}, 2};
  for (std::int64_t strip : std::vector<std::int64_t>{1, 4, 5, 6, rows}) {
    SCOPED_TRACE(testing::Message() << slices << " x " << rows << " x " << columns << ", bands of " << strip);
    const BasinStatistics s = strip_statistics(shape, reader_of(labels), {-1, false, strip, 0}).whole;
    EXPECT_EQ(s.cells, r.cells);
    EXPECT_EQ(s.box_cells, 5);
    EXPECT_EQ(s.boxes, r.boxes);
    EXPECT_EQ(s.boundary_boxes, r.boundary_boxes);
    EXPECT_TRUE(same_bits(s.basin_entropy, r.sum / static_cast<double>(r.boxes)));
    if (r.boundary_boxes > 0) {
      EXPECT_TRUE(same_bits(s.boundary_basin_entropy, r.boundary_sum / static_cast<double>(r.boundary_boxes)));
    }
    EXPECT_EQ(s.epsilon_cells, r.eps);
    ASSERT_EQ(s.uncertain_fraction.size(), r.tested.size());
    for (std::size_t k = 0; k < r.tested.size(); ++k)
      EXPECT_TRUE(same_bits(s.uncertain_fraction[k],
                            static_cast<double>(r.uncertain[k]) / static_cast<double>(r.tested[k])))
          << "eps " << r.eps[k];
    if (std::isnan(slope)) {
      EXPECT_TRUE(std::isnan(s.uncertainty_exponent)) << s.uncertainty_exponent;
    } else {
      EXPECT_NEAR(s.uncertainty_exponent, slope, 1e-12);  // the same sums, another order
    }
  }
}

// Two basins split along a row (the transpose of the straight boundaries above): only the
// neighbours above and below see it.
std::vector<BasinLabel> split_across_rows(std::int64_t rows, std::int64_t columns, std::int64_t at) {
  std::vector<BasinLabel> labels(static_cast<std::size_t>(rows * columns));
  for (std::int64_t i = 0; i < rows * columns; ++i) labels[static_cast<std::size_t>(i)] = i / columns < at ? 1 : 2;
  return labels;
}

TEST(StripStatistics, TwoDimensionalPlaneAgainstTheDefinitions) {
  for (const auto& [rows, columns] : std::vector<std::pair<std::int64_t, std::int64_t>>{
           {25, 65}, {40, 35}, {33, 50}, {97, 83}, {16, 16}, {20, 23}}) {
    expect_plane_reference(mixed_map(rows * columns, columns, 3, 5), 1, rows, columns);
    expect_plane_reference(split_across_rows(rows, columns, rows / 2 + 1), 1, rows, columns);
  }
  expect_plane_reference(mixed_map(3 * 30 * 45, 45, 4, 6), 3, 30, 45);  // slices of a continuation
  // A horizontal boundary in closed form: f(ε) = 2ε / (R − 2ε) of the cells tested.
  const std::int64_t rows = 64, columns = 40;
  const BasinStatistics s =
      strip_statistics({{rows, columns}, 2}, reader_of(split_across_rows(rows, columns, rows / 2))).whole;
  for (std::size_t k = 0; k < s.epsilon_cells.size(); ++k) {
    const double eps = s.epsilon_cells[k];
    EXPECT_DOUBLE_EQ(s.uncertain_fraction[k], 2.0 * eps / (rows - 2.0 * eps)) << eps;
  }
}

// Fewer than three values of ε (sides under 32 cells): no exponent, on a line as on a plane.
TEST(StripStatistics, NoExponentFromTwoValuesOfEpsilon) {
  const BasinStatistics line = strip_statistics({{16}, 1}, reader_of(mixed_map(16, 16, 3, 3))).whole;
  ASSERT_EQ(line.epsilon_cells, (std::vector<int>{1, 2}));
  EXPECT_TRUE(std::isnan(line.uncertainty_exponent));
  EXPECT_TRUE(std::isnan(line.boundary_dimension));
  const BasinStatistics plane = strip_statistics({{23, 40}, 2}, reader_of(mixed_map(23 * 40, 40, 3, 3))).whole;
  ASSERT_EQ(plane.epsilon_cells, (std::vector<int>{1, 2}));
  EXPECT_TRUE(std::isnan(plane.uncertainty_exponent));
}

TEST(StripStatistics, TwoDimensionalPlaneWithUndecidedCells) {
  // 97 rows: no band height above divides it; ε reaches 8 rows, beyond every small band.
  const std::vector<BasinLabel> labels = mixed_map(97 * 83, 83, 3, 1);
  expect_same_for_strips(labels, {{97, 83}, 2});
}

TEST(StripStatistics, ManyBasinsAndWideEpsilon) {
  const std::vector<BasinLabel> labels = mixed_map(160 * 131, 131, 6, 2);
  const BasinStatistics whole = test::statistics_of(labels, {{160, 131}, 2});
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

// Newton's basins of z³ = 1, a Wada boundary (test_wada.cpp): the verdict and every count of the
// merging method from bands of any height, down to bands thinner than the test's halo.
TEST(StripStatistics, WadaBoundary) {
  const int n = 96;
  const std::vector<BasinLabel> labels = test::newton_basins(n);
  const BasinStatistics whole = test::statistics_of(labels, {{n, n}, 2});
  ASSERT_EQ(whole.wada.planes_tested, 1);
  ASSERT_GT(whole.wada.boundary_cells, 100);
  ASSERT_TRUE(whole.wada.wada()) << whole.wada.verdict();
  expect_same_for_strips(labels, {{n, n}, 2});
  expect_same_for_strips(labels, {{1, n, n}, 2}, 0);
}

}  // namespace
}  // namespace cs
