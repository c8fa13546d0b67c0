// The engine's bitwise promises: the tiled, vectorised kernel computes what the scalar step
// computes, lane by lane; and no way of cutting the grid into blocks (as ranks and threads
// do) changes a bit of any output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <memory>
#include <random>

#include "engine/lane_tile.hpp"
#include "numerics/methods/hybrid_leapfrog.hpp"
#include "physics/energy_wells.hpp"
#include "physics/coupled_oscillators.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/double_well.hpp"
#include "physics/z2_damping.hpp"
#include "io/spec_parser.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <class S>
class TiledKernel : public ::testing::Test {};
using Scenes = ::testing::Types<DampedOscillator, Z2Damping, DoubleWell, CoupledOscillators>;
TYPED_TEST_SUITE(TiledKernel, Scenes);

template <class S, bool Uniform>
void check_tile_against_scalar_steps() {
  using M = HybridLeapfrog;
  constexpr int W = 64, D = S::dof;
  constexpr Carry carry{true, true};
  constexpr int steps = 300;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5), positive(0.05, 0.3);
  auto tile = std::make_unique<LaneTile<S, M, W>>();
  std::vector<LaneState<D>> lanes(W);
  std::vector<ParamsOf<S, double>> params(W);
  // Read by each scene in its own order: (ω, γ), (ω, γ), (a, γ), (ω₁², ω₂², g, γ).
  double base[4] = {1.1, 0.1, 0.4, 0.05};
  const auto uniform = S::params_from(base);
  for (int i = 0; i < W; ++i) {
    double values[4] = {1.1, 0.1, 0.4, 0.05};
    if (!Uniform)
      for (double& v : values) v = v + positive(rng) * 0.5;
    params[i] = S::params_from(values);
    LaneState<D> x{};
    for (int d = 0; d < D; ++d) x.q[d] = u(rng), x.p[d] = u(rng);
    x.z = 1.0 + 0.5 * u(rng) / 1.5;  // z > 0: scene B's z' = … − γz² runs away for z ≪ 0
    x.mu = u(rng);
    M::start<S>(x, params[i]);
    lanes[i] = x;
    tile->set_lane(i, x);
    tile->set_parameters(i, params[i], M::coefficients<S>(0.01, params[i], x));
  }
  LaneState<D> x0{};
  auto uniform_coef = M::coefficients<S>(0.01, uniform, x0);
  advance<S, M, carry, Uniform>(*tile, steps, uniform, uniform_coef, 0.0, 0.01, [](int) {});
  for (int i = 0; i < W; ++i) {
    auto x = lanes[i];
    const auto& c = Uniform ? uniform : params[i];
    auto k = M::coefficients<S>(0.01, c, x);
    for (int s = 0; s < steps; ++s) M::step<S, carry>(x, c, k);
    auto y = tile->lane(i);
    ASSERT_TRUE(std::isfinite(x.q[0]) && std::isfinite(x.z)) << "lane " << i << " blew up";
    for (int d = 0; d < D; ++d) {
      ASSERT_TRUE(same_bits(x.q[d], y.q[d])) << "lane " << i;
      ASSERT_TRUE(same_bits(x.p[d], y.p[d])) << "lane " << i;
    }
    ASSERT_TRUE(same_bits(x.z, y.z)) << "lane " << i;
    ASSERT_TRUE(same_bits(x.mu, y.mu)) << "lane " << i;
    ASSERT_TRUE(same_bits(log_lambda<S>(x), log_lambda<S>(y))) << "lane " << i;
  }
}

TYPED_TEST(TiledKernel, EqualsScalarStepsBitForBitWithUniformParameters) {
  check_tile_against_scalar_steps<TypeParam, true>();
}

TYPED_TEST(TiledKernel, EqualsScalarStepsBitForBitWithPerLaneParameters) {
  check_tile_against_scalar_steps<TypeParam, false>();
}

// Each verdict's count over every block (trap_verdict is counted per block).
std::vector<double> verdict_totals(const std::vector<double>& counts) {
  std::vector<double> totals(kTrapVerdicts, 0.0);
  for (std::size_t k = 0; k < counts.size(); ++k) totals[k % kTrapVerdicts] += counts[k];
  return totals;
}

// A block's settlement records (engine/settlement_records.hpp) are its own: the distinct
// (q, p, period) of its lanes, in the order they settled. Over the whole grid, any cut into blocks
// meets the same ones.
std::set<std::vector<double>> record_set(const std::vector<double>& records) {
  constexpr std::size_t kWidth = 3;  // q, p, period: the one-dof scenes these tests map
  std::set<std::vector<double>> set;
  for (std::size_t k = 0; k + kWidth <= records.size(); k += kWidth)
    set.insert(std::vector<double>(records.begin() + static_cast<std::ptrdiff_t>(k),
                                   records.begin() + static_cast<std::ptrdiff_t>(k + kWidth)));
  return set;
}

void expect_identical(const test::Datasets& a, const test::Datasets& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, values] : a) {
    const auto& other = b.at(name);
    if (name == "trap_verdict") {
      EXPECT_EQ(verdict_totals(values), verdict_totals(other));
      continue;
    }
    if (name == "basin_records") {
      EXPECT_EQ(record_set(values), record_set(other));
      continue;
    }
    ASSERT_EQ(values.size(), other.size()) << name;
    EXPECT_EQ(std::memcmp(values.data(), other.data(), values.size() * sizeof(double)), 0)
        << name << " differs";
  }
}

// Blocks of 1, 37 and 500 points put lanes into different slots, tiles and finisher batches
// than one block of the whole grid does.
TEST(EngineBlocks, AnySplitGivesTheSameBits) {
  const std::string basins = R"(
    [scene]
    name = "double_well"
    [integrator]
    t_end = 30.0
    h = 0.03
    [grid]
    q_0 = { from = -2.5, to = 2.5, n = 24 }
    p_0 = { from = -2.0, to = 2.0, n = 21 }
    [measures]
    basin = {}
    final_state = true)";
  auto whole = test::run_in_memory(basins);
  for (std::int64_t block : {1, 37, 500})
    expect_identical(whole, test::run_in_memory(basins, {}, block));

  const std::string sync = R"(
    [scene]
    name = "coupled_oscillators"
    [integrator]
    t_end = 20.0
    [grid]
    g = { from = -0.2, to = 1.0, n = 9 }
    gamma = { from = 0.0, to = 0.05, n = 7 }
    [measures]
    sync = { window = [10.0, 20.0] }
    final_state = true
    trajectory = { every = 100 })";
  auto whole_sync = test::run_in_memory(sync);
  for (std::int64_t block : {1, 10})
    expect_identical(whole_sync, test::run_in_memory(sync, {}, block));
}

// Every lane of a basin map against scalar steps of its own initial state. Lanes stop early at
// different times (refilling their slots at random), and the step count is not a multiple of
// the engine's chunk, so lanes reach the finisher tile out of step with each other (an
// overflow of that tile once went unnoticed here; UBSan's bounds check sees it).
TEST(EngineBlocks, EveryLaneEqualsScalarStepsThroughTheFinisher) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "double_well"
    [integrator]
    h = 0.01
    t_end = 10.07
    [grid]
    q_0 = { from = -2.0, to = 2.0, n = 41 }
    p_0 = { from = -1.5, to = 1.5, n = 37 }
    [measures]
    basin = {}
    final_state = true)");
  ParamsOf<DoubleWell, double> c{1.0, 0.1};
  const auto q0 = linspace(-2.0, 2.0, 41), p0 = linspace(-1.5, 1.5, 37);
  int early = 0;
  for (std::size_t i = 0; i < q0.size(); ++i) {
    for (std::size_t j = 0; j < p0.size(); ++j) {
      std::size_t cell = i * p0.size() + j;
      double settle = r["settle_time"][cell];
      long steps = std::isnan(settle) ? 1007 : std::lround(settle / 0.01);
      early += steps < 1007;
      LaneState<1> x{};
      x.q[0] = q0[i];
      x.p[0] = p0[j];
      x.z = 1.0;
      HybridLeapfrog::start<DoubleWell>(x, c);
      auto k = HybridLeapfrog::coefficients<DoubleWell>(0.01, c, x);
      for (long s = 0; s < steps; ++s) HybridLeapfrog::step<DoubleWell, Carry{true, true}>(x, c, k);
      ASSERT_TRUE(same_bits(r["final_q"][cell], x.q[0])) << "cell " << cell << " settle " << settle << " steps " << steps << " q " << r["final_q"][cell] << " vs " << x.q[0];
      ASSERT_TRUE(same_bits(r["final_p"][cell], x.p[0])) << "cell " << cell;
      ASSERT_TRUE(same_bits(r["final_z"][cell], x.z)) << "cell " << cell;
      ASSERT_TRUE(same_bits(r["final_log_lambda"][cell], x.mu)) << "cell " << cell;
    }
  }
  EXPECT_GT(early, 300);  // enough lanes stop early to scramble the slots
}

// A grid over h (stability and accuracy maps) integrates each h as its own slice: each slice
// equals a run with that h and no h axis, bit for bit.
TEST(EngineBlocks, StepSizeAxisSlicesEqualSeparateRuns) {
  const std::string map = R"(
    [scene]
    name = "double_well"
    [integrator]
    t_end = 12.0
    [grid]
    h = { values = [0.01, 0.05, 0.3, 0.5] }
    q_0 = { from = -3.0, to = 3.0, n = 13 }
    [measures]
    basin = {}
    final_state = true)";
  auto all = test::run_in_memory(map, {}, 5);
  const char* hs[] = {"0.01", "0.05", "0.3", "0.5"};
  for (std::size_t i = 0; i < 4; ++i) {
    auto one = test::run_in_memory(map, {"grid.h={values=[" + std::string(hs[i]) + "]}"});
    for (const auto& [name, values] : one) {
      if (name == "trap_verdict") {  // per block: each verdict's count over the slice's 3 blocks
        ASSERT_EQ(values.size(), static_cast<std::size_t>(kTrapVerdicts));
        for (int v = 0; v < kTrapVerdicts; ++v) {
          double sum = 0.0;
          for (std::size_t b = 0; b < 3; ++b) sum += all[name][(i * 3 + b) * kTrapVerdicts + v];
          EXPECT_EQ(values[static_cast<std::size_t>(v)], sum) << "verdict " << v << " h " << hs[i];
        }
        continue;
      }
      // Per block, of any length: the settled lanes' records, which the labels compared here
      // come from.
      if (name == "basin_records") continue;
      const std::size_t width = values.size() / 13;
      ASSERT_EQ(values.size(), 13u * width) << name;
      for (std::size_t k = 0; k < values.size(); ++k)
        ASSERT_TRUE(same_bits(values[k], all[name][i * 13 * width + k])) << name << " h " << hs[i];
    }
  }
  EXPECT_GT(std::count(all["status"].begin(), all["status"].end(), 1.0), 0);  // h = 0.5 fails
}

}  // namespace
}  // namespace cs
