// io/linspace: numpy.linspace's values bit for bit, as the grid's axes use them.
#include <bit>
#include <cstdint>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "io/linspace.hpp"
#include "io/spec_parser.hpp"
#include "support/spec_parsing.hpp"

namespace cs {
namespace {

using test::kDoubleWell;
using test::parse;

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// numpy.linspace, bit for bit. The expected values were produced with numpy 1.24.2:
//   /usr/bin/python3 -c "import numpy as np; y = np.linspace(FROM, TO, N);
//                        print([(i, float(y[i]).hex()) for i in INDICES])"
// Where noted, they differ from the naive from + i * (to - from) / (n - 1).
struct LinspaceCase {
  double from, to;
  std::int64_t n;
  std::vector<std::pair<std::int64_t, double>> expected;  // (index, numpy's value)
};

const std::vector<LinspaceCase> kLinspaceCases = {
    // np.linspace(-3.0, 3.0, 512): differs from the naive formula at 139 indices.
    {-0x1.8p+1,
     0x1.8p+1,
     512,
     {{0, -0x1.8000000000000p+1},
      {1, -0x1.7e7f3f9fcfe7fp+1},
      {2, -0x1.7cfe7f3f9fcfep+1},
      {100, -0x1.d369b4da6d36ap+0},
      {255, -0x1.80c0603018200p-8},
      {256, 0x1.80c0603018000p-8},
      {257, 0x1.2090482412080p-6},
      {383, 0x1.7f3f9fcfe7f40p+0},
      {510, 0x1.7e7f3f9fcfe7ep+1},
      {511, 0x1.8000000000000p+1}}},
    // np.linspace(0.0, 1.0, 7)
    {0.0,
     1.0,
     7,
     {{0, 0x0.0p+0},
      {1, 0x1.5555555555555p-3},
      {2, 0x1.5555555555555p-2},
      {3, 0x1.0p-1},
      {4, 0x1.5555555555555p-1},
      {5, 0x1.aaaaaaaaaaaaap-1},
      {6, 0x1.0p+0}}},
    // np.linspace(0.1, 0.7, 13)
    {0x1.999999999999ap-4,
     0x1.6666666666666p-1,
     13,
     {{0, 0x1.999999999999ap-4},
      {1, 0x1.3333333333333p-3},
      {2, 0x1.999999999999ap-3},
      {3, 0x1.0p-2},
      {4, 0x1.3333333333333p-2},
      {5, 0x1.6666666666666p-2},
      {6, 0x1.999999999999ap-2},
      {7, 0x1.cccccccccccccp-2},
      {8, 0x1.0p-1},
      {9, 0x1.1999999999999p-1},
      {10, 0x1.3333333333333p-1},
      {11, 0x1.4ccccccccccccp-1},
      {12, 0x1.6666666666666p-1}}},
    // np.linspace(0.0, 5e-324, 4): the step underflows to 0, numpy's i / div * delta branch.
    {0.0,
     0x0.0000000000001p-1022,
     4,
     {{0, 0.0}, {1, 0.0}, {2, 0x0.0000000000001p-1022}, {3, 0x0.0000000000001p-1022}}},
    // np.linspace(1.0, 0.0, 3): descending.
    {1.0, 0.0, 3, {{0, 0x1.0p+0}, {1, 0x1.0p-1}, {2, 0.0}}},
    // np.linspace(5.0, -5.0, 1): a single point is `from`.
    {5.0, -5.0, 1, {{0, 0x1.4p+2}}},
    // np.linspace(-2.5, 7.3, 1000): differs from the naive formula at 238 indices.
    {-2.5,
     0x1.d333333333333p+2,
     1000,
     {{0, -0x1.4p+1},
      {1, -0x1.3ebe8d59d7ebfp+1},
      {3, -0x1.3c3ba80d87c3cp+1},
      {333, 0x1.888888888888cp-1},
      {499, 0x1.329279e01f294p+1},
      {500, 0x1.33d3ec86473d4p+1},
      {666, 0x1.0222222222223p+2},
      {997, 0x1.d1f1c08d0b1f2p+2},
      {998, 0x1.d29279e01f294p+2},
      {999, 0x1.d333333333333p+2}}},
    // np.linspace(0.001, 1000.0, 9)
    {0x1.0624dd2f1a9fcp-10,
     1000.0,
     9,
     {{0, 0x1.0624dd2f1a9fcp-10},
      {1, 0x1.f400e56041894p+6},
      {2, 0x1.f400624dd2f1bp+7},
      {3, 0x1.770028f5c28f6p+8},
      {4, 0x1.f40020c49ba5ep+8},
      {5, 0x1.38800c49ba5e3p+9},
      {6, 0x1.7700083126e98p+9},
      {7, 0x1.b58004189374cp+9},
      {8, 0x1.f4p+9}}},
};

TEST(Linspace, MatchesNumpyBitForBit) {
  for (const LinspaceCase& c : kLinspaceCases) {
    const std::vector<double> y = linspace(c.from, c.to, c.n);
    ASSERT_EQ(std::ssize(y), c.n);
    for (const auto& [i, expected] : c.expected)
      EXPECT_EQ(bits(y[i]), bits(expected))
          << "linspace(" << c.from << ", " << c.to << ", " << c.n << ")[" << i << "] = " << y[i]
          << ", numpy: " << expected;
  }
}

TEST(Linspace, GridAxisUsesIt) {
  const RunSpec spec = parse(kDoubleWell + "[grid]\nq_0 = { from = -3, to = 3.0, n = 512 }\n");
  EXPECT_EQ(spec.axes[0].values, linspace(-3.0, 3.0, 512));
  EXPECT_EQ(bits(spec.axes[0].values[255]), bits(-0x1.80c0603018200p-8));
}

TEST(Linspace, NoPointsForNonPositiveCounts) {
  EXPECT_TRUE(linspace(0.0, 1.0, 0).empty());
  EXPECT_TRUE(linspace(0.0, 1.0, -3).empty());
}

}  // namespace
}  // namespace cs
