// The Wada test (engine/wada_test.hpp, run by engine/strip_statistics.hpp on every 2-D plane of
// a map) on label maps whose answer is known: Newton's method for z³ = 1, whose three basins
// share one boundary (the Julia set: every boundary point of one basin is a boundary point of
// all three), and three sectors meeting at a point, whose boundaries meet only there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>
#include <vector>

#include "basin_maps.hpp"
#include "engine/wada_test.hpp"

namespace cs {
namespace {

using test::newton_basins;
using test::sectors;
using test::statistics_of;
using test::wada_of;

TEST(WadaTest, NewtonsBasinsAreWadaAtEveryResolution) {
  for (int n : {128, 256}) {
    const WadaTest w = wada_of(newton_basins(n), 1, n);
    ASSERT_TRUE(w.applies());
    EXPECT_EQ(w.planes_tested, 1);
    EXPECT_TRUE(w.wada()) << n << ": " << w.verdict();
    EXPECT_GE(w.covered_fraction(kWadaVerdictRadius), 0.99) << n;
    // Coverage grows with the radius, and every cell touching all three basins is covered at 1.
    for (int r = 1; r < kWadaMaxRadius; ++r) EXPECT_LE(w.covered_fraction(r), w.covered_fraction(r + 1));
    EXPECT_GE(w.covered_fraction(1), w.touching_fraction());
    EXPECT_GT(w.touching_fraction(), 0.5) << n;
  }
}

// Along a ray between two sectors, the third sector's boundary is as far as the ray is from the
// centre: only a fixed number of cells near the centre is covered, out of a boundary whose length
// grows like n. The covered fraction halves when n doubles.
TEST(WadaTest, SectorsMeetingAtAPointAreNotWada) {
  const WadaTest coarse = wada_of(sectors(256), 1, 256);
  const WadaTest fine = wada_of(sectors(512), 1, 512);
  for (const WadaTest* w : {&coarse, &fine}) {
    ASSERT_TRUE(w->applies());
    EXPECT_FALSE(w->wada()) << w->verdict();
    EXPECT_LT(w->covered_fraction(kWadaMaxRadius), 0.1);
  }
  EXPECT_NEAR(coarse.covered_fraction(kWadaVerdictRadius) / fine.covered_fraction(kWadaVerdictRadius), 2.0, 0.2);
  EXPECT_NEAR(coarse.touching_fraction() / fine.touching_fraction(), 2.0, 0.2);
}

TEST(WadaTest, UndecidedCellsAreLeftOutAndTwoBasinsAreNotTested) {
  std::vector<std::int32_t> labels = newton_basins(128);
  // Undecided cells sprinkled over the map change neither the verdict nor much the fraction.
  for (std::size_t i = 0; i < labels.size(); i += 97) labels[i] = 0;
  const WadaTest sprinkled = wada_of(labels, 1, 128);
  EXPECT_TRUE(sprinkled.wada()) << sprinkled.verdict();
  // Two basins: basin 3 merged into 2.
  for (auto& l : labels) l = l == 3 ? 2 : l;
  const WadaTest two = wada_of(labels, 1, 128);
  EXPECT_FALSE(two.applies());
  EXPECT_TRUE(std::isnan(two.touching_fraction()));
  EXPECT_NE(two.verdict().find("three basins or more"), std::string::npos);
}

// Planes are tested one by one and their counts added up.
TEST(WadaTest, PlanesOfAMapAreCountedTogether) {
  std::vector<std::int32_t> labels = newton_basins(128);
  const WadaTest one = wada_of(labels, 1, 128);
  const std::vector<std::int32_t> second = sectors(128);
  labels.insert(labels.end(), second.begin(), second.end());
  const WadaTest both = wada_of(labels, 2, 128);
  const WadaTest alone = wada_of(second, 1, 128);
  EXPECT_EQ(both.planes_tested, 2);
  EXPECT_EQ(both.boundary_cells, one.boundary_cells + alone.boundary_cells);
  EXPECT_EQ(both.covered[2], one.covered[2] + alone.covered[2]);
}

// The statistics of a map run the test on the planes of a 2-D map of initial conditions, per
// slice of the leading axes.
TEST(WadaTest, BasinStatisticsCarriesIt) {
  const BasinStatistics s = statistics_of(newton_basins(128), {{128, 128}, 2});
  EXPECT_TRUE(s.wada.wada());
  const BasinStatistics line = statistics_of(newton_basins(128), {{128 * 128}, 1});
  EXPECT_FALSE(line.wada.applies());
}

// The merging method against its definition, computed by brute force: a decided cell is on a
// boundary when its 3 × 3 neighbourhood holds two basins or more; for each basin j, the merged
// map's boundary is the cells of j beside another basin and the cells of another basin beside
// j; a boundary cell's distance to it is the least chessboard distance to any of those cells
// (searched over the whole plane, capped at kWadaMaxRadius + 1), and covered[r − 1] counts the
// boundary cells whose largest distance over j is at most r. Maps: Newton's basins and an
// irregular one of 4 basins with undecided specks, 48 × 48 and 41 × 57.
WadaTest wada_by_definition(const std::vector<BasinLabel>& labels, std::int64_t rows, std::int64_t columns) {
  const auto at = [&](std::int64_t r, std::int64_t c) { return labels[static_cast<std::size_t>(r * columns + c)]; };
  std::vector<BasinLabel> basins;
  for (BasinLabel l : labels)
    if (l != 0 && std::find(basins.begin(), basins.end(), l) == basins.end()) basins.push_back(l);
  const auto near = [&](std::int64_t r, std::int64_t c) {  // the basins of the 3 × 3 neighbourhood
    std::vector<BasinLabel> met;
    for (std::int64_t rr = std::max<std::int64_t>(r - 1, 0); rr <= std::min(r + 1, rows - 1); ++rr)
      for (std::int64_t cc = std::max<std::int64_t>(c - 1, 0); cc <= std::min(c + 1, columns - 1); ++cc)
        if (at(rr, cc) != 0 && std::find(met.begin(), met.end(), at(rr, cc)) == met.end()) met.push_back(at(rr, cc));
    return met;
  };
  // Each merged map's boundary, as a list of cells.
  std::vector<std::vector<std::pair<std::int64_t, std::int64_t>>> seeds(basins.size());
  for (std::size_t j = 0; j < basins.size(); ++j)
    for (std::int64_t r = 0; r < rows; ++r)
      for (std::int64_t c = 0; c < columns; ++c) {
        if (at(r, c) == 0) continue;
        const auto met = near(r, c);
        if (at(r, c) == basins[j] ? met.size() > 1 : std::find(met.begin(), met.end(), basins[j]) != met.end())
          seeds[j].emplace_back(r, c);
      }
  WadaTest w;
  w.covered.assign(kWadaMaxRadius, 0);
  w.planes_tested = 1;
  for (std::int64_t r = 0; r < rows; ++r)
    for (std::int64_t c = 0; c < columns; ++c) {
      if (at(r, c) == 0 || near(r, c).size() < 2) continue;
      ++w.boundary_cells;
      w.touching_all += near(r, c).size() == basins.size();
      int farthest = 0;
      for (const auto& cells : seeds) {
        std::int64_t distance = kWadaMaxRadius + 1;
        for (const auto& [sr, sc] : cells) distance = std::min(distance, std::max(std::abs(sr - r), std::abs(sc - c)));
        farthest = std::max(farthest, static_cast<int>(distance));
      }
      for (int radius = 1; radius <= kWadaMaxRadius; ++radius)
        w.covered[static_cast<std::size_t>(radius - 1)] += farthest <= radius;
    }
  return w;
}

std::vector<BasinLabel> four_irregular_basins(std::int64_t rows, std::int64_t columns) {
  std::vector<BasinLabel> labels(static_cast<std::size_t>(rows * columns));
  for (std::int64_t r = 0; r < rows; ++r)
    for (std::int64_t c = 0; c < columns; ++c) {
      const double x = static_cast<double>(c) / 9.0, y = static_cast<double>(r) / 7.0;
      const double v = std::sin(x + 2.0 * std::sin(y)) + std::cos(1.7 * y - std::sin(1.3 * x));
      BasinLabel l = static_cast<BasinLabel>(std::floor((v + 2.0) / 4.0 * 3.999)) + 1;
      if ((r * 31 + c * 17) % 53 == 0) l = 0;
      labels[static_cast<std::size_t>(r * columns + c)] = l;
    }
  return labels;
}

TEST(WadaTest, MergingMethodAgainstItsDefinition) {
  struct Plane {
    std::vector<BasinLabel> labels;
    std::int64_t rows, columns;
  };
  for (const Plane& p : {Plane{newton_basins(48), 48, 48}, Plane{four_irregular_basins(48, 48), 48, 48},
                         Plane{four_irregular_basins(41, 57), 41, 57}}) {
    SCOPED_TRACE(testing::Message() << p.rows << " x " << p.columns);
    const WadaTest expected = wada_by_definition(p.labels, p.rows, p.columns);
    ASSERT_GT(expected.boundary_cells, 100);
    ASSERT_LT(expected.covered[0], expected.covered[kWadaMaxRadius - 1]);  // distances vary
    for (std::int64_t strip : {0, 3, 11}) {
      const WadaTest w = strip_statistics({{p.rows, p.columns}, 2}, test::reader_of(p.labels),
                                          {-1, false, strip, 0}).whole.wada;
      EXPECT_EQ(w.boundary_cells, expected.boundary_cells);
      EXPECT_EQ(w.touching_all, expected.touching_all);
      EXPECT_EQ(w.covered, expected.covered);
    }
  }
}

}  // namespace
}  // namespace cs
