// dop853 (numerics/methods/dop853.hpp): the adaptive method's own tests. The typed tests of
// every fixed-step method (test_methods.cpp, test_stability*.cpp) ask what a fixed h does; here:
// the formula's order 8 at a fixed step, the global error proportional to the tolerance, H = λK
// on scene A, and the adaptive lanes of the engine against the closed form and against any cut
// of the grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "engine/lane_tile.hpp"
#include "numerics/methods/dop853.hpp"
#include "physics/damped_oscillator.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

using S = DampedOscillator;
const ParamsOf<S, double> kSceneA{1.0, 0.1};  // ω = 1, γ = 0.1 (the paper's scene A)

// Scene A from q = 1, p = 0: q'' + γq' + ω²q = 0, so with Ω = √(ω² − γ²/4)
//   q = e^(−γt/2)(cos Ωt + γ/(2Ω) sin Ωt),  p = −(ω²/Ω) e^(−γt/2) sin Ωt.
struct Exact {
  double q, p;
};
Exact exact(double t) {
  const double g = 0.1, w = 1.0, big = std::sqrt(w * w - g * g / 4), e = std::exp(-g * t / 2);
  return {e * (std::cos(big * t) + g / (2 * big) * std::sin(big * t)),
          -(w * w / big) * e * std::sin(big * t)};
}

LaneState<1> start_state() {
  LaneState<1> x{};
  x.q[0] = 1.0, x.p[0] = 0.0, x.z = 1.0, x.mu = 0.0;
  x.lambda_numerator = x.lambda_denominator = 1.0;
  return x;
}

double error_at(const LaneState<1>& x, double t) {
  const Exact e = exact(t);
  return std::hypot(x.q[0] - e.q, x.p[0] - e.p);
}

// The 8th-order formula at a fixed step: error ∝ h⁸. From h = 0.5 to 0.25 to 0.125 over t = 10
// the errors (1e-7 … 1e-10) stay far above round-off (10⁴ steps · 1e-16).
TEST(Dop853, FixedStepsConvergeWithOrderEight) {
  std::vector<double> errors;
  for (double h : {0.5, 0.25, 0.125}) {
    LaneState<1> x = start_state();
    const auto n = static_cast<int>(std::lround(10.0 / h));
    for (int i = 0; i < n; ++i) {
      x.t = i * h;
      Dop853::step<S, Carry{false, false}>(x, kSceneA, Dop853::Coef<double>{h});
    }
    errors.push_back(error_at(x, 10.0));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1] / errors[i]);
    EXPECT_NEAR(order, 8.0, 0.3) << "errors " << errors[i - 1] << " " << errors[i];
  }
}

struct AdaptiveRun {
  LaneState<1> x;
  double t, accepted, rejected;
};

// One lane stepped adaptively to t_end, as the tile steps it (carrying z and ln λ, as a run of
// an adaptive method always does: RunPlan).
template <Carry carry = Carry{true, true}>
AdaptiveRun adaptive_run(double rtol, double atol, double t_end, double h0 = 0.01,
                         LaneState<1> start = start_state()) {
  AdaptiveRun r{start, 0.0, 0.0, 0.0};
  double h = h0, last_rejected = 0.0;
  const Dop853::Control control{rtol, atol, t_end, t_end};
  for (int i = 0; i < 100000 && r.t < t_end; ++i) {
    r.x.t = r.t;
    Dop853::attempt<S, carry>(r.x, kSceneA, r.t, h, last_rejected, r.accepted, r.rejected,
                              control);
  }
  return r;
}

// Tolerance proportionality: the controller keeps the embedded estimate (≈ C h⁸ per step) at
// tol, so h ∝ tol^(1/8) and steps ∝ tol^(−1/8); the 8th-order solution's own local error is
// O(h⁹) ∝ tol^(9/8), and summed over the steps the global error ∝ tol^(9/8 − 1/8) = tol¹.
// Checked as the slope of log error against log tol over 1e-5 … 1e-10, and the step count's
// growth as tol^(−1/8).
TEST(Dop853, GlobalErrorIsProportionalToTheTolerance) {
  std::vector<double> tols{1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}, log_tol, log_err;
  double steps_first = 0.0, steps_last = 0.0;
  for (double tol : tols) {
    const AdaptiveRun r = adaptive_run(tol, tol, 20.0);
    ASSERT_EQ(r.t, 20.0) << "tol " << tol;  // lands on t_end exactly
    log_tol.push_back(std::log10(tol));
    log_err.push_back(std::log10(error_at(r.x, 20.0)));
    (tol == tols.front() ? steps_first : steps_last) = r.accepted;
  }
  // Least-squares slope.
  double mt = 0, me = 0;
  for (std::size_t i = 0; i < tols.size(); ++i) mt += log_tol[i], me += log_err[i];
  mt /= tols.size(), me /= tols.size();
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < tols.size(); ++i)
    sxy += (log_tol[i] - mt) * (log_err[i] - me), sxx += (log_tol[i] - mt) * (log_tol[i] - mt);
  const double slope = sxy / sxx;
  EXPECT_NEAR(slope, 1.0, 0.15);
  // Steps grow as tol^(−1/8): 10^(5/8) = 4.2 times more over five decades (±40 %).
  EXPECT_NEAR(steps_last / steps_first, std::pow(10.0, 5.0 / 8.0), 0.4 * std::pow(10.0, 5.0 / 8.0))
      << steps_first << " " << steps_last;
  for (std::size_t i = 0; i < tols.size(); ++i)  // and the error stays near the tolerance
    EXPECT_LT(log_err[i], log_tol[i] + 1.5) << "tol 1e" << log_tol[i];
}

// H = λK is conserved by the flow of scene A (K_z = −γ: λ = e^(γt) exactly, K = K₀e^(−γt)):
// over t = 100 (about 16 periods) at rtol = atol = 1e-10 its drift stays below one tolerance
// per step (the local errors, of a state of size ~1, add up at worst), and ln λ is γt to
// round-off (its increments are exact: h·γ).
TEST(Dop853, ConservesHOnSceneAToTheTolerance) {
  const AdaptiveRun r = adaptive_run<Carry{true, true}>(1e-10, 1e-10, 100.0);
  ASSERT_EQ(r.t, 100.0);
  const LaneState<1> x0 = start_state();
  const double h0 = K<S>(x0.q, x0.p, x0.z, kSceneA, 0.0);
  const double h1 = std::exp(r.x.mu) * K<S>(r.x.q, r.x.p, r.x.z, kSceneA, 100.0);
  EXPECT_LT(std::fabs(h1 - h0), r.accepted * 1e-10) << h0 << " " << h1 << " " << r.accepted;
  EXPECT_NEAR(r.x.mu, 0.1 * 100.0, 1e-12);
  EXPECT_LT(error_at(r.x, 100.0), 1e-8);
  EXPECT_GT(r.accepted, 0.0);
}

// z is in the error norm though it does not feed back on scene A: the lane at rest (q = p = 0)
// has z' = −γz alone, z = e^(−γt), and without z in the norm it had no error to control (it
// stepped to h_max = t_end at once, z off by 10⁻⁷ … 5·10⁻⁶ at rtol 10⁻¹⁰). With it, z ends
// within a few tolerances relative to its size, as q and p do.
TEST(Dop853, ZIsErrorControlledWhereItDoesNotFeedBack) {
  LaneState<1> rest = start_state();
  rest.q[0] = 0.0;
  for (double tol : {1e-7, 1e-10}) {
    const AdaptiveRun r = adaptive_run(tol, tol, 20.0, 0.01, rest);
    ASSERT_EQ(r.t, 20.0);
    const double z = std::exp(-0.1 * 20.0);
    EXPECT_LT(std::fabs(r.x.z - z), 20 * tol * z) << "tol " << tol << " z " << r.x.z;
    EXPECT_GT(r.accepted, 1.0) << "tol " << tol;  // not one step over the whole interval
  }
}

// A step the controller cannot shrink enough (a NaN force: err is not finite) is rejected over
// and over until h falls below t's rounding, and the lane breaks down instead of hanging.
TEST(Dop853, AnAttemptThatNeverPassesBreaksTheLaneDown) {
  LaneState<1> x = start_state();
  x.q[0] = NAN;
  double t = 1.0, h = 0.1, last_rejected = 0.0, accepted = 0.0, rejected = 0.0;
  const Dop853::Control control{1e-8, 1e-8, 10.0, 10.0};
  int attempts = 0;
  for (; attempts < 1000 && !(x.broken > 0.0); ++attempts)
    Dop853::attempt<S, Carry{true, true}>(x, kSceneA, t, h, last_rejected, accepted, rejected,
                                          control);
  EXPECT_GT(x.broken, 0.0);
  EXPECT_EQ(accepted, 0.0);
  EXPECT_EQ(t, 1.0);
  EXPECT_LT(attempts, 100);  // h/3 a rejection: 2^-52 from 0.1 in ~33
}

// dop853.f's controller: after a rejection the next step shrinks by at most facc1 = 1/0.333 and
// grows by at most 6 after an acceptance, except that the step accepted right after a rejection
// proposes no more than itself (hnew = min(hnew, h)). From h = 5 at rtol 1e-10 on scene A the
// first attempts are rejected; every step then follows those bounds exactly, to t = 20.
TEST(Dop853, TheControllerKeepsDop853fsBounds) {
  LaneState<1> x = start_state();
  double t = 0.0, h = 5.0, last_rejected = 0.0, accepted = 0.0, rejected = 0.0;
  const Dop853::Control control{1e-10, 1e-10, 20.0, 20.0};
  int after_rejection = 0;
  while (t < 20.0 && accepted + rejected < 10000) {
    const double h_tried = h, was_rejected = last_rejected, accepted_before = accepted;
    Dop853::attempt<S, Carry{true, true}>(x, kSceneA, t, h, last_rejected, accepted, rejected, control);
    const bool accept = accepted > accepted_before;
    // The bounds are products and quotients of h: 1e-15 allows their one rounding.
    if (!accept) {
      EXPECT_LT(h, h_tried);
      EXPECT_GE(h, h_tried * 0.333 * (1.0 - 1e-15));
    } else if (t < 20.0) {
      EXPECT_LE(h, 6.0 * h_tried * (1.0 + 1e-15));
      if (was_rejected > 0.0) {
        EXPECT_LE(h, h_tried) << "the step after a rejection grew";
        ++after_rejection;
      }
    }
  }
  EXPECT_EQ(t, 20.0);
  EXPECT_GT(rejected, 0.0);
  EXPECT_GT(after_rejection, 0);
  EXPECT_LT(error_at(x, t), 1e-8);
}

// The engine: every lane ends at t_end, at the closed form within the tolerance; the same bits
// for any cut of the grid into blocks (as ranks and threads cut it).
const char* kSceneAGrid = R"(
  [scene]
  name = "damped_oscillator"
  [integrator]
  method = "dop853"
  rtol = 1e-10
  atol = 1e-10
  h = 0.01
  t_end = 20.0
  [grid]
  q_0 = { from = -1.0, to = 1.0, n = 37 }
  p_0 = { from = -1.0, to = 1.0, n = 29 }
  [measures]
  final_state = true)";

TEST(Dop853, EngineLanesEndAtTheClosedFormAndAnyCutGivesTheSameBits) {
  const test::Datasets whole = test::run_in_memory(kSceneAGrid);
  const std::vector<double>& q = whole.at("final_q");
  const std::vector<double>& p = whole.at("final_p");
  const std::vector<double>& status = whole.at("status");
  ASSERT_EQ(q.size(), 37u * 29u);
  // The solution is linear in (q0, p0): (q, p)(t) = q0·(q_1, p_1)(t) + p0·(q_2, p_2)(t), with
  // (q_1, p_1) the exact() above and (q_2, p_2) = (p_1, −q_1 − γ p_1)/−ω²… written out:
  const double g = 0.1, big = std::sqrt(1.0 - g * g / 4), t = 20.0, e = std::exp(-g * t / 2);
  const double c = std::cos(big * t), s = std::sin(big * t);
  const double q1 = e * (c + g / (2 * big) * s), p1 = -(1.0 / big) * e * s;
  const double q2 = e * s / big, p2 = e * (c - g / (2 * big) * s);
  double worst = 0.0;
  for (int i = 0; i < 37; ++i)
    for (int j = 0; j < 29; ++j) {
      const double q0 = -1.0 + 2.0 * i / 36, p0 = -1.0 + 2.0 * j / 28;
      const std::size_t k = static_cast<std::size_t>(i) * 29 + static_cast<std::size_t>(j);
      EXPECT_EQ(status[k], 0.0);
      worst = std::max(worst, std::hypot(q[k] - (q0 * q1 + p0 * q2), p[k] - (q0 * p1 + p0 * p2)));
    }
  EXPECT_LT(worst, 1e-8);
  for (std::int64_t block : {1, 37, 500}) {
    const test::Datasets cut = test::run_in_memory(kSceneAGrid, {}, block);
    for (const char* name : {"final_q", "final_p", "status"}) {
      const std::vector<double>& a = whole.at(name);
      const std::vector<double>& b = cut.at(name);
      ASSERT_EQ(a.size(), b.size());
      EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(double)))
          << name << " block " << block;
    }
  }
}

// A basin map with dop853: the double well's two wells, the energy trap deciding each lane, and
// the labels those of the fixed-step reference where the wells are far from the boundary.
TEST(Dop853, DoubleWellBasinMapSettlesEveryLane) {
  const test::Datasets r = test::run_in_memory(R"(
    [scene]
    name = "double_well"
    [integrator]
    method = "dop853"
    rtol = 1e-8
    t_end = 100.0
    [grid]
    q_0 = { from = -3.0, to = 3.0, n = 24 }
    p_0 = { from = -3.0, to = 3.0, n = 21 }
    [measures]
    basin = {}
    final_state = true)");
  const std::vector<double>& basin = r.at("basin");
  const std::vector<double>& settle = r.at("settle_time");
  int left = 0, right = 0;
  for (std::size_t k = 0; k < basin.size(); ++k) {
    left += basin[k] == -1.0, right += basin[k] == 1.0;
    EXPECT_GE(settle[k], 0.0);
    EXPECT_LE(settle[k], 100.0);
  }
  EXPECT_EQ(left + right, static_cast<int>(basin.size()));
  // The map is symmetric under (q, p) → (−q, −p): about half each.
  EXPECT_GT(left, 0.4 * basin.size());
  EXPECT_GT(right, 0.4 * basin.size());
}

}  // namespace
}  // namespace cs
