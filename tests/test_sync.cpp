// The on-line synchronization measures against the same quantities computed afterwards, by
// other formulas, from a stored trajectory sampled every step.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <string>

#include "engine/sync_tracker.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

// The engine samples synchronization on its looks at the lanes, here every 16 steps (the
// trajectory interval); the window [20, 50] becomes steps 2000 … 4992, the looks inside it.
TEST(SyncMeasures, MatchValuesComputedFromTheStoredTrajectory) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "coupled_oscillators"
    [integrator]
    t_end = 60.0
    [grid]
    g = { values = [0.0, 0.3, 0.8] }
    [measures]
    sync = { window = [20.0, 50.0] }
    trajectory = { every = 16 })");
  const double h = 0.01, w1 = std::sqrt(1.2), w2 = std::sqrt(0.8);
  const std::size_t samples = 6000 / 16 + 1, first = 2000 / 16, last = 4992 / 16;
  for (std::size_t g = 0; g < 3; ++g) {
    const double* q1 = &r["traj_q1"][g * samples];
    const double* q2 = &r["traj_q2"][g * samples];
    const double* p1 = &r["traj_p1"][g * samples];
    const double* p2 = &r["traj_p2"][g * samples];
    // Phases from complex amplitudes, unwrapped the textbook way.
    std::complex<double> sum = 0.0;
    std::vector<double> th1, th2;
    for (std::size_t n = first; n <= last; ++n) {
      std::complex<double> u1(q1[n], -p1[n] / w1), u2(q2[n], -p2[n] / w2);
      sum += std::polar(1.0, std::arg(u1) - std::arg(u2));
      th1.push_back(std::arg(u1));
      th2.push_back(std::arg(u2));
    }
    auto unwrap = [](std::vector<double>& th) {
      for (std::size_t i = 1; i < th.size(); ++i)
        th[i] = th[i - 1] + std::remainder(th[i] - th[i - 1], 2 * std::numbers::pi);
    };
    unwrap(th1);
    unwrap(th2);
    double d1 = th1.back() - th1.front(), d2 = th2.back() - th2.front();
    double window = static_cast<double>((last - first) * 16) * h;
    SCOPED_TRACE("g index " + std::to_string(g));
    // Same samples, different formulas: agreement to round-off accumulated over 188 terms.
    EXPECT_NEAR(r["sync_r"][g], std::abs(sum) / double(last - first + 1), 1e-12);
    EXPECT_NEAR(r["sync_phase_drift"][g], (d1 - d2) / window, 1e-12);
    EXPECT_NEAR(r["sync_freq_ratio"][g], d1 / d2, 1e-12);
    std::complex<double> u1(q1[last], -p1[last] / w1), u2(q2[last], -p2[last] / w2);
    EXPECT_NEAR(r["sync_amplitude"][g], std::min(std::abs(u1), std::abs(u2)), 1e-12);
  }
}

// Oscillator 2 started at rest stays there (its force ω₂²q₂ + 2g q₁²q₂ vanishes): it has no
// phase and no frequency. The cell is a valid result (status 0); the ratio is NaN and the
// amplitude, which the dataset's description points to, is exactly 0.
TEST(SyncMeasures, AnOscillatorAtRestHasNoFrequencyRatioAndZeroAmplitude) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "coupled_oscillators"
    [integrator]
    t_end = 40.0
    [grid]
    q2_0 = { values = [0.0, -1.0] }
    [measures]
    sync = { window = [10.0, 40.0] })");
  EXPECT_EQ(r["status"][0], 0.0);
  EXPECT_EQ(r["sync_amplitude"][0], 0.0);
  EXPECT_TRUE(std::isnan(r["sync_freq_ratio"][0]));
  EXPECT_EQ(r["sync_r"][0], 0.0);  // no sample has a defined phase difference
  // The paper's start (q2 = -1) beside it: every measure defined.
  EXPECT_EQ(r["status"][1], 0.0);
  EXPECT_GT(r["sync_amplitude"][1], 0.1);
  EXPECT_TRUE(std::isfinite(r["sync_freq_ratio"][1]));
}

// Looks come every 0.2 time units at h = 0.01; a window between two looks would hold one
// sample, whose "phase-locking value" is 1 by construction.
TEST(SyncMeasures, AWindowHoldingFewerThanTwoLooksIsRefused) {
  const std::string spec = R"(
    [scene]
    name = "coupled_oscillators"
    [integrator]
    t_end = 40.0
    [measures]
    sync = { window = [10.05, 10.25] })";
  try {
    test::run_in_memory(spec);
    FAIL() << "a one-look window was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fewer than two looks"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(test::run_in_memory(spec, {"measures.sync.window=[10.0, 10.2]"}));
}

// For g < 0 the coupling -|g| q1^2 q2^2 is unbounded below: from (2, -2) the oscillators escape
// to infinity in finite time. The cell is flagged diverged (status 1) and its NaN measures are
// covered by the flag; the bounded cell (g = 0.8) beside it has finite measures.
TEST(SyncMeasures, EscapeForNegativeCouplingIsFlaggedDiverged) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "coupled_oscillators"
    [initial]
    q1 = 2.0
    q2 = -2.0
    [integrator]
    t_end = 40.0
    [grid]
    g = { values = [-1.0, 0.8] }
    [measures]
    sync = { window = [10.0, 40.0] }
    final_state = true)");
  EXPECT_EQ(r["status"][0], 1.0);
  EXPECT_EQ(r["status"][1], 0.0);
  for (const char* name : {"sync_r", "sync_phase_drift", "sync_freq_ratio", "sync_amplitude",
                           "final_q1", "final_p2", "final_H"})
    EXPECT_TRUE(std::isfinite(r[name][1])) << name;
}

}  // namespace
}  // namespace cs

namespace cs {
namespace {

// A phase that turns backwards unwraps as well as one that turns forwards: oscillator 1 runs
// retrograde (p₁ = +ω₁ sin ω₁t, so θ₁ = −ω₁t), oscillator 2 forwards, sampled every 0.2 time
// units (|Δθ| ≤ 0.26, far below π) over 100: the frequency ratio is −ω₁/ω₂ and the drift of
// θ₁ − θ₂ is −ω₁ − ω₂, whichever way each phase crosses ±π (16 wraps of θ₁, 11 of θ₂).
TEST(SyncTracker, UnwrapsPhasesTurningEitherWay) {
  const double omega1 = 1.3, omega2 = 0.7, h = 0.01;
  const std::int64_t every = 20, last = 10000;
  SyncTracker tracker;
  bool done = false;
  for (std::int64_t n = 0; n <= last; n += every) {
    const double t = static_cast<double>(n) * h;
    done = tracker.sample(n, 0, last, std::cos(omega1 * t), omega1 * std::sin(omega1 * t),
                          std::cos(omega2 * t), -omega2 * std::sin(omega2 * t), omega1, omega2);
  }
  ASSERT_TRUE(done);
  const SyncResult r = tracker.result(static_cast<double>(last) * h);
  // Each unwrapped phase adds 500 wrapped differences, rounded at ulp(130) ≈ 3e-14: at most
  // 1.4e-11 in θ over the window, ≤ 2e-13 in these.
  EXPECT_NEAR(r.freq_ratio, -omega1 / omega2, 1e-12);
  EXPECT_NEAR(r.phase_drift, -omega1 - omega2, 1e-12);
  EXPECT_NEAR(r.amplitude, 1.0, 1e-12);
}

}  // namespace
}  // namespace cs
