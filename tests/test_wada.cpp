// The Wada test (engine/wada_test.hpp, run by engine/strip_statistics.hpp on every 2-D plane of
// a map) on label maps whose answer is known: Newton's method for z³ = 1, whose three basins
// share one boundary (the Julia set: every boundary point of one basin is a boundary point of
// all three), and three sectors meeting at a point, whose boundaries meet only there.
#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace cs
