// dop853 (numerics/methods/dop853.hpp): the adaptive method's own tests. The typed tests of
// every fixed-step method (test_methods.cpp, test_stability*.cpp) ask what a fixed h does; here:
// the formula's order 8 at a fixed step, the global error proportional to the tolerance, H = λK
// on scene A, the error norm and next step of one attempt against dop853.f's formulas, and the
// adaptive lanes of the engine against the closed form and against any cut of the grid.
#include <gtest/gtest.h>

#include <algorithm>
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

// The error norm and the step-size controller against dop853.f, computed independently here.
// One attempt from a state of scene A: the 12 stage rates from the method's own `stage` (the
// stages' nodes and matrix are what FixedStepsConvergeWithOrderEight checks), everything after
// them -- the 8th-order solution, sk, the 5th- and 3rd-order estimates, their norm and the next
// h -- recomputed in long double from dop853.f's published weights, written out below, and
// dop853.f's formulas:
//   sk_i = atol + rtol·max(|y0_i|, |y1_i|),  y1 = y0 + h·Σ b_j k_j
//   err5 = Σ_i (Σ_j er_j k_j,i / sk_i)²,  err3 = Σ_i ((Σ_j b_j k_j,i − bhh1 k_1,i − bhh2 k_9,i
//          − bhh3 k_12,i) / sk_i)²
//   err = |h|·err5·sqrt(1/(n·(err5 + 0.01·err3))),  accepted when err ≤ 1
//   fac11 = err^(1/8) (beta = 0: no Lund stabilisation), safe = 0.9, facc1 = 1/0.333,
//   facc2 = 1/6: accepted: hnew = h/max(facc2, min(facc1, fac11/safe)), min(hnew, hmax), and
//   min(hnew, h) right after a rejection; rejected: hnew = h/min(facc1, fac11/safe).
// n = 3 on scene A: q, p and z (K_z = −γ is constant, so ln λ is not integrated but
// incremented exactly).
namespace hairer {
// dop853.f: b1, b6 … b12 (b2 … b5 = 0)
constexpr long double b[12] = {5.42937341165687622380535766363e-2L, 0, 0, 0, 0,
                               4.45031289275240888144113950566L,
                               1.89151789931450038304281599044L,
                               -5.8012039600105847814672114227L,
                               3.1116436695781989440891606237e-1L,
                               -1.52160949662516078556178806805e-1L,
                               2.01365400804030348374776537501e-1L,
                               4.47106157277725905176885569043e-2L};
// bhh1, bhh2, bhh3: the 3rd-order weights of stages 1, 9 and 12
constexpr long double bhh1 = 0.244094488188976377952755905512L,
                      bhh2 = 0.733846688281611857341361741547L,
                      bhh3 = 0.220588235294117647058823529412e-1L;
// er1, er6 … er12
constexpr long double er[12] = {0.1312004499419488073250102996e-1L, 0, 0, 0, 0,
                                -0.1225156446376204440720569753e1L,
                                -0.4957589496572501915214079952L,
                                0.1664377182454986536961530415e1L,
                                -0.3503288487499736816886487290L,
                                0.3341791187130174790297318841L,
                                0.8192320648511571246570742613e-1L,
                                -0.2235530786388629525884427845e-1L};
}  // namespace hairer

using Point1 = contact_field::Point<1, double>;

struct Expected {
  long double err, err5, err3;
  bool accept;
  bool interior;  // fac11/safe strictly between facc2 and facc1: neither bound clamps hnew
  long double h_next;
  double rounding;  // a bound on the relative difference of the code's h_next (double)
};

// dop853.f's norm and controller for one attempt of step hs from y0 with stage rates r (scene
// A's components q, p, z).
Expected expected_attempt(const Point1& y0, const Point1* r, double hs, double rtol, double atol,
                          bool last_rejected, double h_max) {
  const long double h = hs;
  long double err5 = 0, err3 = 0;
  double condition = 1.0;
  for (int m = 0; m < 3; ++m) {
    auto comp = [m](const Point1& y) { return m == 0 ? y.q[0] : m == 1 ? y.p[0] : y.z; };
    long double k4 = 0, e5 = 0, abs5 = 0, abs3 = 0;
    for (int j = 0; j < 12; ++j) {
      k4 += hairer::b[j] * comp(r[j]);
      e5 += hairer::er[j] * comp(r[j]);
      abs5 += std::fabs(hairer::er[j] * comp(r[j]));
      abs3 += std::fabs(hairer::b[j] * comp(r[j]));
    }
    const long double e3 =
        k4 - hairer::bhh1 * comp(r[0]) - hairer::bhh2 * comp(r[8]) - hairer::bhh3 * comp(r[11]);
    abs3 += std::fabs(hairer::bhh1 * comp(r[0])) + std::fabs(hairer::bhh2 * comp(r[8])) +
            std::fabs(hairer::bhh3 * comp(r[11]));
    const long double y1 = comp(y0) + h * k4;
    const long double sk = atol + rtol * std::max(std::fabs((long double)comp(y0)), std::fabs(y1));
    err5 += (e5 / sk) * (e5 / sk);
    err3 += (e3 / sk) * (e3 / sk);
    // How much the code's double sums may lose to cancellation: Σ|w_j k_j| / |Σ w_j k_j|.
    condition = std::max({condition, double(abs5 / std::fabs(e5)), double(abs3 / std::fabs(e3))});
  }
  long double deno = err5 + 0.01L * err3;
  if (deno <= 0) deno = 1;
  const long double err = std::fabs(h) * err5 * std::sqrt(1.0L / (3 * deno));
  const long double fac11 = std::pow(err, 0.125L), safe = 0.9L, facc1 = 1 / 0.333L,
                    facc2 = 1 / 6.0L;
  const bool accept = err <= 1;
  const bool interior = facc2 < fac11 / safe && fac11 / safe < facc1;
  long double h_next;
  if (accept) {
    h_next = h / std::max(facc2, std::min(facc1, fac11 / safe));
    h_next = std::min(h_next, (long double)h_max);
    if (last_rejected) h_next = std::min(h_next, h);
  } else {
    h_next = h / std::min(facc1, fac11 / safe);
  }
  // The code sums each component's 8 nonzero products in double (fused: 8 roundings, each at
  // most 2⁻⁵³ of the sum of the magnitudes; its weights, read to doubles, 1 more): relative
  // error ≤ 9·2⁻⁵³·condition in each estimate, twice that in err5, half of err3's (which
  // dominates the denominator), 1/8 of err's in h_next: ≤ 3.4·2⁻⁵³·condition, plus a few
  // roundings of h (1e-15). 8·2⁻⁵³·condition + 1e-15 bounds it with room.
  return {err, err5, err3, accept, interior, h_next, 8 * 0x1p-53 * condition + 1e-15};
}

struct Attempt {
  LaneState<1> x;
  double t, h, last_rejected, accepted, rejected;
};

// The code's attempt: `conclude` on the stage rates r, and `attempt` (which computes its own)
// from the same lane; the two must agree to the bit.
Attempt code_attempt(const LaneState<1>& x0, double h, double last_rejected,
                     const Dop853::Control& k, const Point1* r) {
  Attempt a{x0, 0.0, h, last_rejected, 0.0, 0.0};
  Dop853::conclude<S, Carry{true, true}>(a.x, a.t, a.h, a.last_rejected, a.accepted, a.rejected,
                                         k, r);
  Attempt b{x0, 0.0, h, last_rejected, 0.0, 0.0};
  Dop853::attempt<S, Carry{true, true}>(b.x, kSceneA, b.t, b.h, b.last_rejected, b.accepted,
                                        b.rejected, k);
  EXPECT_EQ(a.h, b.h);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.x.q[0], b.x.q[0]);
  EXPECT_EQ(a.x.z, b.x.z);
  return a;
}

TEST(Dop853, ErrorNormAndNextStepAreDop853fs) {
  LaneState<1> x0 = start_state();
  x0.q[0] = 0.8, x0.p[0] = -0.6, x0.z = 1.7, x0.t = 0.0;
  const Point1 y0{x0};
  struct Case {
    double h, tol;
    bool last_rejected, accepted;  // the branch of the controller the case exercises
  };
  // h and tol chosen so that fac11/safe falls strictly inside (facc2, facc1): the next h is
  // h·safe/err^(1/8), where the safety factor and the norm both show. The reference's err
  // (this state, tol 1e-9) is 0.038, 0.64, 2.08 and 169; 0.01·err3 is 10³ to 10⁵ times err5,
  // so the 0.01 weight sets err (about as 1/sqrt(0.01)); 0.64 and 2.08 lie within a factor
  // sqrt(3) and sqrt(10) of 1, so that the norm's 1/sqrt(n) and the 0.01 decide acceptance too.
  const Case cases[] = {
      {0.30, 1e-9, false, true},
      {0.43, 1e-9, true, true},  // right after a rejection: hnew < h here, so min(hnew, h) = hnew
      {0.50, 1e-9, false, false},
      {0.90, 1e-9, false, false},
  };
  for (const Case& c : cases) {
    Point1 r[12];
    contact_field::unrolled<12>(
        [&](auto i) { r[i] = Dop853::stage<i, S, true, false>(y0, kSceneA, 0.0, c.h, r); });
    const Dop853::Control k{c.tol, c.tol, 100.0, 100.0};
    const Expected e = expected_attempt(y0, r, c.h, c.tol, c.tol, c.last_rejected, k.h_max);
    const Attempt a = code_attempt(x0, c.h, c.last_rejected ? 1.0 : 0.0, k, r);
    ASSERT_EQ(e.accept, c.accepted) << "h " << c.h << " err " << double(e.err);
    ASSERT_TRUE(e.interior) << "h " << c.h << " err " << double(e.err);
    if (c.last_rejected) {
      ASSERT_LT(e.h_next, c.h);  // min(hnew, h) does not hide safe
    }
    EXPECT_EQ(a.accepted, e.accept ? 1.0 : 0.0) << "h " << c.h << " err " << double(e.err);
    EXPECT_EQ(a.rejected, e.accept ? 0.0 : 1.0) << "h " << c.h << " err " << double(e.err);
    EXPECT_EQ(a.t, e.accept ? c.h : 0.0) << "h " << c.h;
    EXPECT_EQ(a.last_rejected, e.accept ? 0.0 : 1.0) << "h " << c.h;
    // The rounding bound is 2e-7 or less here (the error estimates cancel to 1e-8 of their
    // terms); the mutations it must see move h by 3^(1/16) − 1 = 7 % (no 1/sqrt(n)) or more
    // (safe 0.8 for 0.9: 12.5 %; weight 0.1 for 0.01: ~15 %).
    ASSERT_LT(e.rounding, 1e-3);
    EXPECT_NEAR(a.h / double(e.h_next), 1.0, e.rounding)
        << "h " << c.h << " err " << double(e.err) << " (err5 " << double(e.err5) << ", err3 "
        << double(e.err3) << ") next h " << a.h << " expected " << double(e.h_next);
  }
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
