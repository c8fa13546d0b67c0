// The recurrence mapper's core (engine/recurrence/): cells, a lane's visited set, and the state
// machine fed closed-form orbits directly — a limit cycle, a spiral into a fixed point, a
// quasi-periodic orbit on a torus, the chaotic logistic map — against the cells they cross.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <vector>

#include "engine/recurrence/attractor_cells.hpp"
#include "engine/recurrence/cell_grid.hpp"
#include "engine/recurrence/cell_set.hpp"
#include "engine/recurrence/recurrence_tracker.hpp"

namespace cs {
namespace {

constexpr double kPi = std::numbers::pi;
using Grid2 = CellGrid<2>;

Grid2 square_grid(double lower, double upper, double cell) {
  return Grid2({lower, lower}, {upper, upper}, {cell, cell}, {0.0, 0.0});
}

// Feeds x(k), k = 0, 1, ..., until the tracker finishes or `limit` samples.
template <int N>
Recurrence run(RecurrenceTracker<N>& tracker, const CellGrid<N>& grid, const RecurrenceOptions& o,
               const std::function<std::array<double, N>(std::int64_t)>& x, std::int64_t limit) {
  tracker.reset(o.max_cells);
  for (std::int64_t k = 0; k < limit; ++k) {
    const auto point = x(k);
    if (finished(tracker.feed(point.data(), grid, o))) break;
  }
  return tracker.state();
}

// The cells a curve crosses, each with the measure of the curve's parameter it holds, from a
// fine partition of the parameter: the reference the located cells are compared with.
std::map<std::uint64_t, double> crossed_cells(
    const Grid2& grid, const std::function<std::array<double, 2>(double)>& curve,
    const std::function<double(double, double)>& measure, int pieces) {
  std::map<std::uint64_t, double> cells;
  for (int i = 0; i < pieces; ++i) {
    const double a = static_cast<double>(i) / pieces, b = static_cast<double>(i + 1) / pieces;
    const auto x = curve(0.5 * (a + b));
    cells[grid.key(x.data())] += measure(a, b);
  }
  return cells;
}

// Every located cell is one the curve crosses, and every crossed cell whose measure promises at
// least `hits` samples among `locate` is located.
int expect_located_cover(const std::vector<std::uint64_t>& located,
                         const std::map<std::uint64_t, double>& crossed, double locate,
                         double hits) {
  for (std::uint64_t key : located) EXPECT_TRUE(crossed.count(key)) << "cell " << key;
  int heavy = 0;
  for (const auto& [key, mass] : crossed) {
    if (mass * locate < hits) continue;
    ++heavy;
    EXPECT_TRUE(std::binary_search(located.begin(), located.end(), key))
        << "cell " << key << " holds " << mass << " of the orbit";
  }
  EXPECT_GT(heavy, 0);
  return heavy;
}

TEST(CellGrid, KeysCentresAndTheBox) {
  const Grid2 grid = square_grid(-1.0, 1.0, 0.1);
  EXPECT_EQ(grid.cells(0), 20);
  const double x[2] = {0.05, -0.95};  // cell (10, 0)
  EXPECT_EQ(grid.key(x), 10u);
  const double y[2] = {-1.0, 0.99};  // cell (0, 19)
  EXPECT_EQ(grid.key(y), 19u * 20u);
  EXPECT_NEAR(grid.centre(10u)[0], 0.05, 1e-15);
  EXPECT_NEAR(grid.centre(10u)[1], -0.95, 1e-15);
  const double outside[2] = {1.0, 0.0}, below[2] = {0.0, -1.0000001}, nan[2] = {NAN, 0.0};
  EXPECT_EQ(grid.key(outside), Grid2::kOutside);
  EXPECT_EQ(grid.key(below), Grid2::kOutside);
  EXPECT_EQ(grid.key(nan), Grid2::kOutside);
  EXPECT_THROW(Grid2({0, 0}, {1, 1}, {0.0, 0.1}, {0, 0}), std::invalid_argument);
  EXPECT_THROW(Grid2({0, 0}, {1, 1}, {1e-9, 1e-9}, {0, 0}), std::invalid_argument);  // 10^18 cells
}

TEST(CellGrid, AnglesFoldOntoAWholeNumberOfCells) {
  // Period 2π with cells of about 0.4: 16 cells of 2π/16.
  const CellGrid<2> grid({0.0, -1.0}, {0.0, 1.0}, {0.4, 0.25}, {2 * kPi, 0.0});
  EXPECT_EQ(grid.cells(0), 16);
  EXPECT_DOUBLE_EQ(grid.cell_size(0), 2 * kPi / 16);
  for (double q : {0.1, 1.0, 3.0, 6.2}) {
    const double x[2] = {q, 0.3};
    for (int m : {-7, -1, 1, 3, 100}) {
      const double y[2] = {q + m * 2 * kPi, 0.3};
      EXPECT_EQ(grid.key(x), grid.key(y)) << q << " + " << m << "·2π";
    }
  }
  // Cells 0 and 15 of an angle touch; cells 0 and 2 do not.
  const double first[2] = {0.01, 0.0}, last[2] = {-0.01, 0.0}, third[2] = {0.9, 0.0};
  EXPECT_EQ(grid.index(grid.key(last), 0), 15);
  EXPECT_TRUE(grid.adjacent(grid.key(first), grid.key(last)));
  EXPECT_FALSE(grid.adjacent(grid.key(first), grid.key(third)));
}

// The box's last cell may reach past `upper` (cell_grid.hpp): [0, 1) in cells of 0.3 is 4 cells,
// and 0.95 lies in the fourth. A tiny negative angle is just below the period, in the last cell,
// whatever the number of cells (its folded value rounds to the period itself).
TEST(CellGrid, TheLastCellOfTheBoxAndOfAnAngle) {
  const Grid2 box({0.0, 0.0}, {1.0, 1.0}, {0.3, 0.3}, {0.0, 0.0});
  EXPECT_EQ(box.cells(0), 4);
  const double x[2] = {0.95, 0.1};
  ASSERT_NE(box.key(x), Grid2::kOutside);
  EXPECT_EQ(box.index(box.key(x), 0), 3);
  for (int n = 3; n <= 64; ++n) {
    const CellGrid<2> grid({0.0, -1.0}, {0.0, 1.0}, {2 * kPi / n, 0.25}, {2 * kPi, 0.0});
    ASSERT_EQ(grid.cells(0), n);
    const double y[2] = {-1e-300, 0.1};
    const std::uint64_t key = grid.key(y);
    EXPECT_EQ(grid.index(key, 0), n - 1) << n;
    EXPECT_EQ(grid.index(key, 1), 4) << n;  // (0.1 + 1)/0.25 = 4.4
  }
}

TEST(CellSet, AddsOnceGrowsAndStopsAtItsBound) {
  CellSet set(1000);
  for (std::uint64_t k = 0; k < 1000; ++k)
    EXPECT_EQ(set.visit(k * 7919, false), CellSet::Visit::added);
  EXPECT_EQ(set.size(), 1000u);
  EXPECT_LE(set.capacity(), 2048u);  // at most half full, a power of two
  for (std::uint64_t k = 0; k < 1000; ++k)
    EXPECT_EQ(set.visit(k * 7919, k % 3 == 0), CellSet::Visit::seen);
  EXPECT_EQ(set.visit(5, false), CellSet::Visit::full);
  EXPECT_EQ(set.located(), 334u);
  const auto located = set.located_keys();
  ASSERT_EQ(located.size(), 334u);
  EXPECT_TRUE(std::is_sorted(located.begin(), located.end()));
  EXPECT_EQ(located[1], 3u * 7919u);
  EXPECT_EQ(set.smallest_located(), 0u);
  const std::size_t capacity = set.capacity();
  set.clear();
  EXPECT_EQ(set.size(), 0u);
  EXPECT_FALSE(set.contains(7919));
  EXPECT_EQ(set.capacity(), capacity);  // kept for the next lane
}

// A limit cycle: the circle of radius r, sampled at a golden-angle rotation (equidistributed).
// A convex closed curve crosses as many cells as grid lines, about 8r/c (2πr/c times the mean
// of |cos θ| + |sin θ|, 4/π); all but corners clipped too thinly to be sampled are located.
TEST(RecurrenceTracker, LimitCycleSettlesOnTheCellsOfTheCircle) {
  const Grid2 grid = square_grid(-2.0, 2.0, 0.1);
  const double r = 1.0, cx = 0.03, cy = 0.07, omega = 2 * kPi * (2.0 - std::numbers::phi);
  RecurrenceOptions o;
  o.locate = 4000;
  auto circle = [&](double phase) {
    return std::array<double, 2>{cx + r * std::cos(phase), cy + r * std::sin(phase)};
  };
  RecurrenceTracker<2> tracker;
  ASSERT_EQ(run<2>(
                tracker, grid, o, [&](std::int64_t k) { return circle(omega * k); }, 100000),
            Recurrence::settled);
  // Grid lines x = k/10 in (cx − r, cx + r) and y = k/10 in (cy − r, cy + r), each crossed twice.
  const int crossings = 2 * 20 + 2 * 20;
  const auto crossed = crossed_cells(
      grid, [&](double s) { return circle(2 * kPi * s); }, [](double a, double b) { return b - a; },
      1 << 20);
  EXPECT_EQ(static_cast<int>(crossed.size()), crossings);
  const auto located = tracker.located_keys();
  expect_located_cover(located, crossed, static_cast<double>(o.locate), 10.0);
  EXPECT_NEAR(static_cast<double>(located.size()), 8 * r / 0.1, 4.0);
  EXPECT_EQ(tracker.samples(), tracker.settle_sample() + 1 + o.recurrences - 1 + o.locate);
  // The same cycle met at another phase: the same cells, up to thinly clipped corners.
  RecurrenceTracker<2> other;
  run<2>(
      other, grid, o, [&](std::int64_t k) { return circle(1.234 + omega * k); }, 100000);
  std::vector<std::uint64_t> differ;
  const auto others = other.located_keys();
  std::set_symmetric_difference(located.begin(), located.end(), others.begin(), others.end(),
                                std::back_inserter(differ));
  for (std::uint64_t key : differ) EXPECT_LT(crossed.at(key) * o.locate, 10.0) << key;
  EXPECT_EQ(tracker.representative(), located.front());
  EXPECT_EQ(tracker.representative(), other.representative());
}

// A focus: the spiral r0·e^{−λk} round a point at a cell's centre stays in that cell from the
// first k with r < c/2, k_in = ⌈ln(2r0/c)/λ⌉: one located cell, the run settled by k_in.
TEST(RecurrenceTracker, SpiralIntoAFixedPointSettlesOnItsCell) {
  const Grid2 grid = square_grid(-1.0, 1.0, 0.1);
  const double r0 = 0.8, lambda = 0.05, cx = 0.05, cy = -0.35;
  RecurrenceOptions o;
  RecurrenceTracker<2> tracker;
  const auto spiral = [&](std::int64_t k) {
    const double rk = r0 * std::exp(-lambda * k);
    return std::array<double, 2>{cx + rk * std::cos(1.0 * k), cy + rk * std::sin(1.0 * k)};
  };
  ASSERT_EQ(run<2>(tracker, grid, o, spiral, 100000), Recurrence::settled);
  const std::int64_t k_in = static_cast<std::int64_t>(std::ceil(std::log(2 * r0 / 0.1) / lambda));
  EXPECT_EQ(tracker.located_cells(), 1u);
  const double centre[2] = {cx, cy};
  EXPECT_EQ(tracker.representative(), grid.key(centre));
  EXPECT_LE(tracker.settle_sample(), k_in);
  EXPECT_EQ(tracker.samples(), tracker.settle_sample() + o.recurrences + o.locate);
}

// A quasi-periodic orbit: the rotation by (2π(√2 − 1), 2π(√3 − 1)) on the 2-torus, fed as
// unreduced angles, is dense and equidistributed: its cells are all 16 × 16 of the torus.
TEST(RecurrenceTracker, QuasiPeriodicOrbitCoversTheTorus) {
  const CellGrid<2> grid({0, 0}, {0, 0}, {2 * kPi / 16, 2 * kPi / 16}, {2 * kPi, 2 * kPi});
  const double a1 = 2 * kPi * (std::numbers::sqrt2 - 1), a2 = 2 * kPi * (std::numbers::sqrt3 - 1);
  RecurrenceOptions o;
  o.locate = 4000;  // ~16 samples a cell
  RecurrenceTracker<2> tracker;
  ASSERT_EQ(run<2>(
                tracker, grid, o,
                [&](std::int64_t k) {
                  return std::array<double, 2>{a1 * k, a2 * k};
                },
                100000),
            Recurrence::settled);
  EXPECT_EQ(tracker.located_cells(), 256u);
  EXPECT_EQ(tracker.representative(), 0u);
  // Folding: the same orbit wound m times more round each angle lands in the same cells.
  RecurrenceTracker<2> wound;
  run<2>(
      wound, grid, o,
      [&](std::int64_t k) {
        return std::array<double, 2>{a1 * k + 2 * kPi * (k % 7 - 3), a2 * k - 2 * kPi * (k % 5)};
      },
      100000);
  EXPECT_EQ(wound.located_keys(), tracker.located_keys());
  EXPECT_EQ(wound.settle_sample(), tracker.settle_sample());
}

// A chaotic attractor: the logistic map at r = 4 drawn as (x_k, x_{k+1}) lies on the parabola
// y = 4x(1 − x), with the invariant density 1/(π√(x(1 − x))): a cell holds the measure
// (2/π)(asin√b − asin√a) of the x it spans. Cells holding at least 20 samples' worth are located.
TEST(RecurrenceTracker, ChaoticSequenceSettlesOnManyCellsOfItsAttractor) {
  const double c = 1.0 / 64;
  const Grid2 grid = square_grid(-c, 1.0 + c, c);
  RecurrenceOptions o;
  o.locate = 20000;
  std::vector<double> x{0.1234};
  for (int k = 0; k < 200000; ++k) x.push_back(4.0 * x.back() * (1.0 - x.back()));
  RecurrenceTracker<2> tracker;
  ASSERT_EQ(run<2>(
                tracker, grid, o,
                [&](std::int64_t k) {
                  return std::array<double, 2>{x[k], x[k + 1]};
                },
                199999),
            Recurrence::settled);
  const auto crossed = crossed_cells(
      grid,
      [](double s) {
        return std::array<double, 2>{s, 4 * s * (1 - s)};
      },
      [](double a, double b) {
        return 2 / kPi * (std::asin(std::sqrt(b)) - std::asin(std::sqrt(a)));
      },
      1 << 20);
  const int heavy =
      expect_located_cover(tracker.located_keys(), crossed, static_cast<double>(o.locate), 20.0);
  EXPECT_GT(heavy,
            150);  // the reference itself: "many cells" (176 crossed, the cover of 2^20 pieces)
  RecordProperty("located_cells", static_cast<int>(tracker.located_cells()));
  RecordProperty("settle_sample", static_cast<int>(tracker.settle_sample()));
}

TEST(RecurrenceTracker, LeavingTheBoxDivergingAndTooManyCells) {
  const Grid2 grid = square_grid(-1.0, 1.0, 0.1);
  RecurrenceOptions o;
  RecurrenceTracker<2> tracker;
  // Outside from k = 10 (x = 1.0): the 21st sample outside in a row (k = 30) gives up.
  EXPECT_EQ(run<2>(
                tracker, grid, o,
                [](std::int64_t k) {
                  return std::array<double, 2>{0.1 * k, 0.0};
                },
                1000),
            Recurrence::left_box);
  EXPECT_EQ(tracker.samples(), 31);
  EXPECT_EQ(run<2>(
                tracker, grid, o,
                [](std::int64_t k) {
                  return std::array<double, 2>{k < 50 ? 0.0 : INFINITY, 0.0};
                },
                1000),
            Recurrence::diverged);
  EXPECT_EQ(tracker.samples(), 51);
  o.max_cells = 50;  // a new cell every sample: the 51st is refused
  EXPECT_EQ(run<2>(
                tracker, grid, o,
                [](std::int64_t k) {
                  return std::array<double, 2>{-0.95 + 0.1 * (k % 20), -0.95 + 0.1 * (k / 20)};
                },
                1000),
            Recurrence::too_many_cells);
  EXPECT_EQ(tracker.samples(), 51);
  EXPECT_EQ(tracker.visited_cells(), 50u);
}

// Samples outside the box neither count as recurrences nor reset the count (an attractor that
// grazes the box's edge still settles), and a lane that returns is not lost.
TEST(RecurrenceTracker, ExcursionsOutsideTheBoxDoNotResetTheCount) {
  const Grid2 grid = square_grid(-1.0, 1.0, 0.5);
  RecurrenceOptions o;
  o.recurrences = 30;
  o.locate = 10;
  RecurrenceTracker<2> tracker;
  // Two cells alternating, every third sample outside (never 21 in a row).
  const auto orbit = [](std::int64_t k) {
    if (k % 3 == 2) return std::array<double, 2>{5.0, 0.0};
    return std::array<double, 2>{k % 2 ? 0.25 : -0.25, 0.25};
  };
  ASSERT_EQ(run<2>(tracker, grid, o, orbit, 1000), Recurrence::settled);
  EXPECT_EQ(tracker.located_cells(), 2u);
  // The last new cell at k = 1; 30 recurrences need 45 samples (a third are outside): found at
  // k = 46; ten more samples locate, the outside ones counted but adding no cell.
  EXPECT_EQ(tracker.settle_sample(), 1);
  EXPECT_EQ(tracker.samples(), 1 + 45 + 10);
}

TEST(CellSet, SketchIsTheKeysOfSmallestHash) {
  CellSet set(100);
  std::vector<std::uint64_t> keys;
  for (std::uint64_t k = 0; k < 50; ++k)
    set.visit(1000 + 37 * k, true), keys.push_back(1000 + 37 * k);
  std::sort(keys.begin(), keys.end(),
            [](std::uint64_t a, std::uint64_t b) { return cell_hash(a) < cell_hash(b); });
  std::vector<std::uint64_t> expected(keys.begin(), keys.begin() + 8);
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(set.sketch(8), expected);
  EXPECT_EQ(set.sketch(100).size(), 50u);  // all of a small set
}

// Cells of 10 × 10, the second variable an angle (wraps).
AttractorCells ten_by_ten() { return AttractorCells({10, 10}, {false, true}); }
std::uint64_t cell(int i, int j) { return static_cast<std::uint64_t>(i + 10 * j); }

TEST(AttractorCells, TouchingSetsAreOneAttractorOthersStayApart) {
  AttractorCells cells = ten_by_ten();
  cells.add({cell(2, 2), cell(3, 2)});
  cells.add({cell(4, 3)});              // touches (3, 2) at a corner
  cells.add({cell(6, 2)});              // two cells from (4, 3): apart
  cells.add({cell(0, 9)});              // the angle wraps: touches (0, 0) and (1, 0)…
  cells.add({cell(1, 0), cell(9, 5)});  // …so these join it, and (9, 5) with them
  cells.add({cell(9, 0)});  // the first variable does not wrap: (9, 0) is far from (0, 9)
  const auto components = cells.components();
  ASSERT_EQ(components.size(), 4u);
  EXPECT_EQ(components[0], (std::vector<std::uint64_t>{cell(1, 0), cell(9, 5), cell(0, 9)}));
  EXPECT_EQ(components[1], (std::vector<std::uint64_t>{cell(9, 0)}));
  EXPECT_EQ(components[2], (std::vector<std::uint64_t>{cell(2, 2), cell(3, 2), cell(4, 3)}));
  EXPECT_EQ(components[3], (std::vector<std::uint64_t>{cell(6, 2)}));
  EXPECT_EQ(cells.component_of(cell(4, 3)), 2);
  EXPECT_EQ(cells.component_of(cell(5, 5)), -1);
}

// A set that bridges two attractors merges them, whatever the order the sets came in: the
// table is the same for any cut of the grid into blocks.
TEST(AttractorCells, ComponentsDoNotDependOnTheOrderOfTheSets) {
  std::vector<std::vector<std::uint64_t>> sets = {
      {cell(1, 1)}, {cell(5, 5), cell(5, 6)}, {cell(2, 2), cell(3, 3)}, {cell(8, 8)}, {cell(4, 4)}};
  std::vector<int> order = {0, 1, 2, 3, 4};
  std::vector<std::vector<std::uint64_t>> first;
  do {
    AttractorCells cells = ten_by_ten();
    for (int i : order) cells.add(sets[static_cast<std::size_t>(i)]);
    const auto components = cells.components();
    if (first.empty()) first = components;
    EXPECT_EQ(components, first);
  } while (std::next_permutation(order.begin(), order.end()));
  // (1,1)-(2,2)-(3,3)-(4,4)-(5,5): one chain; (8,8) apart.
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].size(), 6u);
  EXPECT_EQ(first[1], (std::vector<std::uint64_t>{cell(8, 8)}));
}

}  // namespace
}  // namespace cs
