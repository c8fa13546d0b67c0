// The paper's statements about its four scenes (sec. 3.2), checked through the whole engine.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "support/run_in_memory.hpp"

namespace cs {
namespace {

double max_abs_after(const std::vector<double>& traj, std::size_t from) {
  double m = 0.0;
  for (std::size_t i = from; i < traj.size(); ++i) m = std::max(m, std::fabs(traj[i]));
  return m;
}

// Fig. 1: "The case (B) has a slower decay than the case (A) with the same values of
// parameters." Compared by the envelope max|q| over 40 ≤ t ≤ 50.
TEST(PaperScenes, ZSquaredDampingDecaysSlowerThanLinear) {
  const std::string body = R"(
    [integrator]
    h = 0.01
    t_end = 50.0
    [measures]
    trajectory = { every = 10 })";
  auto a = test::run_in_memory("[scene]\nname = \"damped_oscillator\"\n" + body);
  auto b = test::run_in_memory("[scene]\nname = \"z2_damping\"\n" + body);
  const std::size_t from = 400;  // sample 400 is t = 40
  double envelope_a = max_abs_after(a["traj_q"], from), envelope_b = max_abs_after(b["traj_q"], from);
  // A decays like e^{−γt/2}: at t = 40, e^{−2} ≈ 0.135 of the start.
  EXPECT_NEAR(envelope_a, std::exp(-0.05 * 40), 0.02);
  // Measured ratio 1.47 (z decays, and with it B's damping rate 2γz); the integrator's error
  // at h = 0.01 is ~1e-4, so the margin below is physics, not numerics.
  EXPECT_GT(envelope_b, 1.3 * envelope_a);
}

// Fig. 2: from q = ±2 the motions are mirror images. The step is odd in (q, p) in IEEE
// arithmetic too, so the mirror holds bit for bit.
TEST(PaperScenes, DoubleWellFromPlusAndMinusTwoAreExactMirrors) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "double_well"
    [integrator]
    t_end = 50.0
    [grid]
    q_0 = { values = [-2.0, 2.0] }
    [measures]
    trajectory = { every = 1 })");
  const auto& q = r["traj_q"];
  const auto& p = r["traj_p"];
  const std::size_t n = q.size() / 2;
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(q[i], -q[n + i]) << "sample " << i;
    ASSERT_EQ(p[i], -p[n + i]) << "sample " << i;
  }
  // From +2 an accurate reference (DOP853, PHYSICS.md) crosses the barrier and ends in the
  // left well, so from −2 it ends in the right one.
  EXPECT_GT(q[n - 1], 0.5);
}

// Fig. 3: with g = 0.8 the oscillators synchronize, with g = 0 they do not. Uncoupled, the
// phase difference drifts at ω₁ − ω₂ = √1.2 − √0.8; locked, it does not drift.
TEST(PaperScenes, CoupledOscillatorsLockWithCouplingOnly) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "coupled_oscillators"
    [integrator]
    t_end = 100.0
    [grid]
    g = { values = [0.0, 0.8] }
    [measures]
    sync = { window = [50.0, 100.0] })");
  const double free_drift = std::sqrt(1.2) - std::sqrt(0.8);
  // Uncoupled: drift within the sampling error of one window (a phase error < π over 50).
  EXPECT_NEAR(r["sync_phase_drift"][0], free_drift, 0.02);
  EXPECT_NEAR(r["sync_freq_ratio"][0], std::sqrt(1.2 / 0.8), 0.02);
  EXPECT_LT(r["sync_r"][0], 0.5);
  // Coupled: locked.
  EXPECT_NEAR(r["sync_phase_drift"][1], 0.0, 0.01);
  EXPECT_NEAR(r["sync_freq_ratio"][1], 1.0, 0.01);
  EXPECT_GT(r["sync_r"][1], 0.9);
  EXPECT_GT(r["sync_amplitude"][1], 0.3);  // the lock is measured on a living motion
}

// The phases' ω are each lane's own (the scene's natural_frequencies at the lane's parameters,
// taken once at its load): over a grid of ω₁² the uncoupled, undamped oscillator 1 moves on
// the ellipse q₁² + (p₁/ω₁)² = 1 (from q₁ = 1, p₁ = 0), so its phase amplitude is 1 in every
// lane. RK4 at ω₁h ≤ 0.018 loses |R(iω₁h)| − 1 ≈ (ω₁h)⁶/144 < 3e-13 per step, < 3e-9 over the
// 10⁴ steps; oscillator 2's amplitude 2 keeps min(a₁, a₂) = a₁. With another lane's ω₁ the
// amplitude swings between 1 and ω₁/ω: at t = 100 it was 0.645 for ω₁² = 0.5 with the spec's
// 1.2. The frequency ratio is ω₁/ω₂ within a phase error < π/4 at the window's ends (0.02).
TEST(PaperScenes, SyncPhasesUseEachLanesOwnFrequencies) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "coupled_oscillators"
    omega1_sq = 1.2
    g = 0.0
    gamma = 0.0
    [initial]
    q1 = 1.0
    p1 = 0.0
    q2 = 2.0
    p2 = 0.0
    [integrator]
    method = "rk4"
    h = 0.01
    t_end = 100.0
    [grid]
    omega1_sq = { values = [0.5, 1.2, 3.0] }
    [measures]
    sync = { window = [50.0, 100.0] })");
  const double omega1_sq[] = {0.5, 1.2, 3.0};
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(omega1_sq[i]);
    EXPECT_NEAR(r["sync_amplitude"][i], 1.0, 1e-8);
    EXPECT_NEAR(r["sync_freq_ratio"][i], std::sqrt(omega1_sq[i] / 0.8), 0.02);
  }
}

}  // namespace
}  // namespace cs
