// Issue 4, run level: what a sweep reports at the edges of stability. The limits themselves come
// from the eigenvalues of each method's one-step map (test_stability.cpp); here whole runs go
// through the engine (spec → plan → block runner → tiled kernel), and their `status` and
// measures are checked against predictions from that same map.
//
// Scene A (ω = 1, γ = 0.1) maps (q, p) linearly: x_n = Mⁿ x₀ (support/linear_step_map.hpp).
//  * Just below the limit, h = limit·(1 − ε), every eigenvalue has |λⱼ| < 1. Writing
//    x₀ = Σⱼ cⱼvⱼ (right eigenvectors), |x_n,i| ≤ Σⱼ |V_ij| |cⱼ| |λⱼ|ⁿ: a bound that also says how
//    fast the run decays, asserted at every trajectory sample and at t_end.
//  * Just above it, h = limit·(1 + ε), the dominant eigenvalue has ρ = |λ₁| > 1. With w its left
//    eigenvector (wᵀM = λ₁wᵀ), wᵀx_n = λ₁ⁿ wᵀx₀, so max(|q_n|, |p_n|) ≥ ρⁿ |wᵀx₀| / ‖w‖₁ and n
//    steps with ρⁿ |wᵀx₀| / ‖w‖₁ ≥ 10·kDivergenceBound carry every cell with wᵀx₀ ≠ 0 past the
//    bound: t_end is that many steps (the most any cell needs). The origin is a fixed point of
//    every method (wᵀx₀ = 0) and must stay unflagged, with no NaN anywhere, in the same run.
// ε = 1e-3: the limits are known to 1e-13 (≪ ε), and the premises ρ < 1 below and ρ > 1 above
// are asserted from the map before any run. At ε = 1e-3 (ω = 1, γ = 0.1):
//   method               h below   ρ below   h above   ρ above   steps (t_end = steps·h)
//   hybrid_leapfrog      1.998     0.9462    2.002     1.0347     612
//   symmetric_leapfrog   1.998     0.9462    2.002     1.0347     559
//   contact_splitting2   1.998     0.9458    2.002     1.0348     557
//   contact_splitting4   1.56903   0.9245    1.57217   1.0457     440
//   contact_splitting6   2.80899   0.8690    2.81461   1.1188     170
//   rk4                  2.90689   0.9915    2.91271   1.0085    2057
// (steps is recomputed by the test and recorded as a property. The two leap-frogs' maps differ
// but have the same trace and determinant, so the same ρ with another growing direction.)
// Just below the limit the second-order methods have two real eigenvalues near −0.9 (the complex
// pair meets on the real axis at h = 1.9975), so κ(V) ≈ 45; just above, one has passed −1.
// RK4's complex pair crosses the unit circle (κ(V) ≈ 1.05).
//
// Scene B (K = (p² + ω²q²)/2 − γz², K_z = −2γz) with the hybrid leap-frog: the λ factors are
// a = 1 − (h/2)K_z = 1 + hγz and b = 1 + (h/2)K_z^{n+1} = 1 − hγz^{n+1}. From q = p = 0 the
// (q, p) part stays exactly 0 and z follows z' = −γz² by the midpoint rule; in u = hγz one step
// is u_½ = u − u²/2, u' = u − u_½², and the step breaks down where a = 1 + u ≤ 0 or
// b = 1 − u' ≤ 0. This scalar recurrence predicts the step at which each cell breaks down.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/run_plan.hpp"
#include "support/all_methods.hpp"
#include "physics/scene_bounds.hpp"
#include "support/format_number.hpp"
#include "support/linear_step_map.hpp"
#include "support/run_in_memory.hpp"
#include "support/stability_theory.hpp"

namespace cs {
namespace {

constexpr double kOmega = 1.0, kGamma = 0.1;
constexpr double kEps = 1e-3;
constexpr double kOk = static_cast<double>(LaneStatus::ok);
constexpr double kDiverged = static_cast<double>(LaneStatus::diverged);
constexpr double kBreakdown = static_cast<double>(LaneStatus::breakdown);

// The limits derived by tests/stability_theory.py (numpy, from the published schemes), which
// test_stability.cpp finds on the code's own map to 1e-9.
template <class M>
struct Limit;
template <>
struct Limit<HybridLeapfrog> {
  static constexpr const char* name = "hybrid_leapfrog";
  static constexpr double h = test::stability_theory::kHybridLeapfrog;
};
template <>
struct Limit<SymmetricLeapfrog> {
  static constexpr const char* name = "symmetric_leapfrog";
  static constexpr double h = test::stability_theory::kSymmetricLeapfrog;
};
template <>
struct Limit<ContactSplitting2> {
  static constexpr const char* name = "contact_splitting2";
  static constexpr double h = test::stability_theory::kContactSplitting2;
};
template <>
struct Limit<ContactSplitting4> {
  static constexpr const char* name = "contact_splitting4";
  static constexpr double h = test::stability_theory::kContactSplitting4;
};
template <>
struct Limit<ContactSplitting6> {
  static constexpr const char* name = "contact_splitting6";
  static constexpr double h = test::stability_theory::kContactSplitting6;
};
template <>
struct Limit<Rk4> {
  static constexpr const char* name = "rk4";
  static constexpr double h = test::stability_theory::kRk4;
};

// The grid of both scene A runs: q_0 slowest, then p_0. Cell 4 is the origin.
const std::vector<double> kQ0 = {-1.0, 0.0, 0.5, 1.0}, kP0 = {-1.0, 0.0, 1.0};
constexpr int kEvery = 32;  // trajectory interval = the engine's chunk: every look is a sample

std::string list(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + test::full_precision(v[i]);
  return s + "]";
}

std::string scene_a_spec(const char* method, double h, long steps) {
  return std::string("[scene]\nname = \"damped_oscillator\"\nomega = 1.0\ngamma = 0.1\n") +
         "[initial]\nz = 1.0\nlambda = 1.0\n" + "[integrator]\nmethod = \"" + method +
         "\"\nh = " + test::full_precision(h) +
         "\nt_end = " + test::full_precision(static_cast<double>(steps) * h) + "\n" +
         "[grid]\nq_0 = { values = " + list(kQ0) + " }\np_0 = { values = " + list(kP0) + " }\n" +
         "[measures]\nfinal_state = true\ntrajectory = { every = " + std::to_string(kEvery) +
         " }\n";
}

struct Eigen2 {
  Eigen::Vector2cd values;
  Eigen::Matrix2cd vectors;  // columns
};

Eigen2 eigen_of(const Eigen::Matrix2d& m) {
  Eigen::EigenSolver<Eigen::Matrix2d> es(m);
  return {es.eigenvalues(), es.eigenvectors()};
}

int dominant(const Eigen::Vector2cd& values) {
  return std::abs(values[0]) >= std::abs(values[1]) ? 0 : 1;
}

// Steps after which the growing mode carries x₀ past 10× the divergence bound (see the top).
long steps_past_bound(const Eigen::Matrix2d& m, double q0, double p0) {
  const Eigen2 left = eigen_of(m.transpose());
  const int k = dominant(left.values);
  const Eigen::Vector2cd w = left.vectors.col(k);
  const double rho = std::abs(left.values[k]);
  const double component = std::abs(w[0] * q0 + w[1] * p0) / (std::abs(w[0]) + std::abs(w[1]));
  return static_cast<long>(
      std::ceil(std::log(10.0 * kDivergenceBound / component) / std::log(rho)));
}

// Componentwise bound on |Mⁿx₀| from the eigen-decomposition (see the top).
struct DecayBound {
  Eigen2 e;
  Eigen::Vector2cd c;
  double at(int i, long n) const {
    double b = 0.0;
    for (int j = 0; j < 2; ++j)
      b += std::abs(e.vectors(i, j)) * std::abs(c[j]) *
           std::pow(std::abs(e.values[j]), static_cast<double>(n));
    return b;
  }
};

DecayBound decay_bound(const Eigen::Matrix2d& m, double q0, double p0) {
  DecayBound d{eigen_of(m), {}};
  d.c = d.e.vectors.fullPivLu().solve(Eigen::Vector2cd(q0, p0));
  return d;
}

const char* const kFinal[] = {"final_q", "final_p", "final_z", "final_log_lambda", "final_H"};
const char* const kTraj[] = {"traj_q", "traj_p", "traj_z", "traj_log_lambda", "traj_H"};

template <class M>
class StabilityRuns : public ::testing::Test {};
using test::AllMethods;
TYPED_TEST_SUITE(StabilityRuns, AllMethods);

TYPED_TEST(StabilityRuns, BoundedJustBelowTheLimitFlaggedJustAbove) {
  using M = TypeParam;
  const char* method = Limit<M>::name;
  const double h_below = Limit<M>::h * (1.0 - kEps), h_above = Limit<M>::h * (1.0 + kEps);
  const Eigen::Matrix2d m_below = test::one_step_matrix<M>(h_below, kOmega, kGamma);
  const Eigen::Matrix2d m_above = test::one_step_matrix<M>(h_above, kOmega, kGamma);
  const double rho_below = test::spectral_radius(m_below),
               rho_above = test::spectral_radius(m_above);
  ASSERT_LT(rho_below, 1.0) << "premise: h = limit·(1 − ε) is stable";
  ASSERT_GT(rho_above, 1.0) << "premise: h = limit·(1 + ε) is unstable";
  ASSERT_GT(m_above.determinant(), 0.0);  // invertible: a nonzero state never maps to 0

  const std::size_t nq = kQ0.size(), np = kP0.size(), cells = nq * np;
  long steps = 0;
  for (double q0 : kQ0)
    for (double p0 : kP0)
      if (q0 != 0.0 || p0 != 0.0) steps = std::max(steps, steps_past_bound(m_above, q0, p0));
  this->RecordProperty("rho_below", test::full_precision(rho_below));
  this->RecordProperty("rho_above", test::full_precision(rho_above));
  this->RecordProperty("steps", static_cast<int>(steps));
  const long samples = steps / kEvery + 1;

  // ---- just below: every cell ok, bounded by the decaying modes, no NaN anywhere ----
  {
    const std::string spec = scene_a_spec(method, h_below, steps);
    ASSERT_EQ(parse_run_spec(spec, {}, "below").steps, steps);
    test::Datasets r;
    ASSERT_NO_THROW(r = test::run_in_memory(spec));
    for (std::size_t i = 0; i < nq; ++i) {
      for (std::size_t j = 0; j < np; ++j) {
        const std::size_t cell = i * np + j;
        EXPECT_EQ(r["status"][cell], kOk) << method << " below, cell " << cell;
        for (const char* name : kFinal) EXPECT_TRUE(std::isfinite(r[name][cell])) << name;
        for (const char* name : kTraj)
          for (long s = 0; s < samples; ++s)
            ASSERT_TRUE(std::isfinite(r[name][cell * samples + s])) << name << " sample " << s;
        // Round-off adds at most ~steps·κ(V)·1e-16 relative (≤ 612·45·1.1e-16 ≈ 3e-12): 1e-9 of the
        // initial bound is a hundredfold margin that still sees any growth.
        const auto bound = decay_bound(m_below, kQ0[i], kP0[j]);
        const double slack = 1e-9 * std::max({bound.at(0, 0), bound.at(1, 0), 1.0});
        auto check = [&](long n, double q, double p) {
          EXPECT_LE(std::fabs(q), bound.at(0, n) + slack)
              << method << " cell " << cell << " step " << n;
          EXPECT_LE(std::fabs(p), bound.at(1, n) + slack)
              << method << " cell " << cell << " step " << n;
        };
        for (long s = 0; s < samples; ++s)
          check(s * kEvery, r["traj_q"][cell * samples + s], r["traj_p"][cell * samples + s]);
        check(steps, r["final_q"][cell], r["final_p"][cell]);
      }
    }
  }

  // ---- just above: every cell with a growing component flagged, the run itself succeeds ----
  {
    const std::string spec = scene_a_spec(method, h_above, steps);
    ASSERT_EQ(parse_run_spec(spec, {}, "above").steps, steps);
    test::Datasets r;
    ASSERT_NO_THROW(r = test::run_in_memory(spec));
    for (std::size_t cell = 0; cell < cells; ++cell) {
      const bool origin = kQ0[cell / np] == 0.0 && kP0[cell % np] == 0.0;
      if (origin) {
        // Unflagged, in the same run as flagged cells: no NaN in any measure, q = p = 0.
        EXPECT_EQ(r["status"][cell], kOk) << method;
        for (const char* name : kFinal) EXPECT_TRUE(std::isfinite(r[name][cell])) << name;
        for (const char* name : kTraj)
          for (long s = 0; s < samples; ++s)
            EXPECT_TRUE(std::isfinite(r[name][cell * samples + s])) << name << " sample " << s;
        EXPECT_EQ(r["final_q"][cell], 0.0);
        EXPECT_EQ(r["final_p"][cell], 0.0);
        continue;
      }
      EXPECT_EQ(r["status"][cell], kDiverged) << method << " above, cell " << cell;
      // The final state is where the lane was flagged: past the bound, not yet overflowed
      // (one chunk grows it by at most ρ³² ≪ 1e300).
      const double q = r["final_q"][cell], p = r["final_p"][cell];
      EXPECT_TRUE(std::isfinite(q) && std::isfinite(p)) << method << " cell " << cell;
      EXPECT_GT(std::max(std::fabs(q), std::fabs(p)), kDivergenceBound)
          << method << " cell " << cell;
      // Its trajectory ends where it failed: samples recorded while healthy, then NaN from
      // the look that flagged it on. A healthy sample is inside the bound and never the origin
      // (M is invertible, x₀ ≠ 0, so Mⁿx₀ ≠ 0: a q = p = 0 sample was never computed).
      const double* tq = &r["traj_q"][cell * samples];
      const double* tp = &r["traj_p"][cell * samples];
      long first_nan = 0;
      while (first_nan < samples && !std::isnan(tq[first_nan])) ++first_nan;
      EXPECT_GE(first_nan, 1) << method << " cell " << cell;
      for (long s = 0; s < first_nan; ++s) {
        EXPECT_LE(std::max(std::fabs(tq[s]), std::fabs(tp[s])), kDivergenceBound)
            << method << " cell " << cell << " sample " << s << " of " << first_nan;
        EXPECT_TRUE(tq[s] != 0.0 || tp[s] != 0.0)
            << method << " cell " << cell << ": sample " << s << " (step " << s * kEvery
            << ") reads q = p = 0, a state the growing lane never had";
      }
      for (const char* name : kTraj)
        for (long s = first_nan; s < samples; ++s)
          ASSERT_TRUE(std::isnan(r[name][cell * samples + s])) << name << " sample " << s;
    }
  }
}

// ---- the λ factor breaks down ----------------------------------------------------------------

// Scene A, where K_z = −γ is constant: the hybrid leap-frog's b = 1 − hγ/2 is ≤ 0 from
// h = 2/γ on, for every step, so the engine flags the lane when it loads it (breaks_down), before
// any step. At h = 1: γ = 2 gives b = 0 exactly (every operand is exact in binary), γ = 2.1 gives
// b = −0.05; γ = 0.1 and 1.9 keep b = 0.95 and 0.05 > 0, and their (q, p) maps are stable
// (ρ = 0.951 and 0.457), so they must run to t_end. γ is a grid axis: per-lane coefficients.
// The trajectory keeps the sound initial state as sample 0 and is NaN from the first step on.
TEST(StabilityRunsSceneA, ConstantLambdaFactorBreakdownIsKnownAtLoad) {
  const std::vector<double> gamma = {0.1, 1.9, 2.0, 2.1};
  const std::string spec = std::string("[scene]\nname = \"damped_oscillator\"\nomega = 1.0\n") +
                           "[initial]\nq = 1.0\np = 0.0\nz = 1.0\nlambda = 1.0\n" +
                           "[integrator]\nmethod = \"hybrid_leapfrog\"\nh = 1.0\nt_end = 10.0\n" +
                           "[grid]\ngamma = { values = " + list(gamma) + " }\n" +
                           "[measures]\nfinal_state = true\ntrajectory = { every = 1 }\n";
  test::Datasets r;
  ASSERT_NO_THROW(r = test::run_in_memory(spec));
  const long samples = 11;
  const double initial[] = {1.0, 0.0, 1.0, 0.0};  // q, p, z, ln λ
  for (std::size_t cell = 0; cell < gamma.size(); ++cell) {
    const bool broken = 1.0 - 0.5 * 1.0 * gamma[cell] <= 0.0;
    EXPECT_EQ(r["status"][cell], broken ? kBreakdown : kOk) << "gamma " << gamma[cell];
    for (const char* name : kFinal)
      EXPECT_EQ(std::isnan(r[name][cell]), broken) << name << " gamma " << gamma[cell];
    for (int v = 0; v < 4; ++v)
      EXPECT_EQ(r[kTraj[v]][cell * samples], initial[v]) << kTraj[v] << " gamma " << gamma[cell];
    for (const char* name : kTraj)
      for (long s = 1; s < samples; ++s)
        EXPECT_EQ(std::isnan(r[name][cell * samples + s]), broken)
            << name << " gamma " << gamma[cell] << " sample " << s;
  }
}

// ---- scene B: the λ factor breaks down -------------------------------------------------------

// The step (1-based) during which a factor first reaches ≤ 0 within `steps`, else 0.
long predicted_breakdown_step(double u, long steps) {
  for (long n = 1; n <= steps; ++n) {
    if (1.0 + u <= 0.0) return n;  // a = 1 + hγzⁿ
    const double u_half = u - 0.5 * u * u;
    u = u - u_half * u_half;
    if (1.0 - u <= 0.0) return n;  // b = 1 − hγzⁿ⁺¹
  }
  return 0;
}

// h = 0.01, γ = 0.1: u = hγz = z/1000. The cells, with the recurrence done by hand:
//   z₀ = −2000  u = −2:    a = −1 at step 1.
//   z₀ = −500   u = −0.5:  u → −0.890625 → −2.5476: a = 0.109 at step 2, a = −1.548 at step 3.
//               The exact flow z = z₀/(1 + γz₀t) itself blows up at t = 1/(γ|z₀|) = 0.02 = 2 h:
//               the breakdown flags a real singularity of the dynamics.
//   z₀ = −1     u = −0.001: exact blow-up at t = 10 (step 1000); the recurrence breaks down
//               at step 1001, inside t_end = 20. (For u < 0 the midpoint's decrement
//               u²(1 + |u|/2)² is smaller than the exact flow's u²/(1 − |u|): it lags the exact
//               singularity slightly, as at z₀ = −500.)
//   z₀ = 0      u = 0 is a fixed point: a = b = 1 throughout.
//   z₀ = 1, 500, 1000   u ∈ (0, 1]: u_½ = u(1 − u/2) ∈ (0, u) so u' = u − u_½² ∈ (u − u², u),
//               which lies in (0, u): u decreases and stays positive, a = 1 + u > 1 and
//               b = 1 − u' ≥ 1 − u₁ > 0 (u₁ = 0.75 from u = 1) — provably never a breakdown.
//   z₀ = 1500   u = 1.5: u_½ = 0.375, u₁ = 1.359: b = −0.359 at step 1.
//   z₀ = 2000   u = 2:   u_½ = 0, u₁ = 2: b = −1 at step 1.
//               The exact flow from z₀ > 0 is regular (z decays like 1/(γt)): this breakdown
//               is the method's alone, from a step too large for the state (b ≤ 0 at step 1
//               for 1.2253 ≤ hγz₀ ≤ 2.9470, the roots of u²(1 − u/2)² = u − 1).
// A trajectory sampled every step (so the engine looks at the lanes every step, chunk = 1)
// shows where: samples 0 … n−1 finite, NaN from sample n on.
TEST(StabilityRunsSceneB, LambdaFactorBreakdownIsFlaggedAtThePredictedStep) {
  const std::vector<double> z0 = {-2000.0, -500.0, -1.0, 0.0, 1.0, 500.0, 1000.0, 1500.0, 2000.0};
  const std::vector<long> expected = {1, 3, 1001, 0, 0, 0, 0, 1, 1};
  constexpr double h = 0.01;
  constexpr long steps = 2000;
  const std::string spec =
      std::string("[scene]\nname = \"z2_damping\"\nomega = 1.0\ngamma = 0.1\n") +
      "[initial]\nq = 0.0\np = 0.0\nlambda = 1.0\n" +
      "[integrator]\nmethod = \"hybrid_leapfrog\"\nh = 0.01\nt_end = 20.0\n" +
      "[grid]\nz_0 = { values = " + list(z0) + " }\n" +
      "[measures]\nfinal_state = true\ntrajectory = { every = 1 }\n";
  ASSERT_EQ(parse_run_spec(spec, {}, "scene B").steps, steps);
  test::Datasets r;
  ASSERT_NO_THROW(r = test::run_in_memory(spec));
  const long samples = steps + 1;
  for (std::size_t cell = 0; cell < z0.size(); ++cell) {
    const long n = predicted_breakdown_step(h * kGamma * z0[cell], steps);
    EXPECT_EQ(n, expected[cell]) << "z0 " << z0[cell];
    RecordProperty("breakdown_step_z0_" + test::full_precision(z0[cell]), static_cast<int>(n));
    EXPECT_EQ(r["status"][cell], n > 0 ? kBreakdown : kOk) << "z0 " << z0[cell];
    for (const char* name : kFinal)
      EXPECT_EQ(std::isnan(r[name][cell]), n > 0) << name << " z0 " << z0[cell];
    for (const char* name : {"traj_q", "traj_p", "traj_z"}) {
      const double* t = &r[name][cell * samples];
      const long first_bad = n > 0 ? n : samples;
      for (long s = 0; s < first_bad; ++s)
        ASSERT_TRUE(std::isfinite(t[s])) << name << " z0 " << z0[cell] << " sample " << s;
      for (long s = first_bad; s < samples; ++s)
        ASSERT_TRUE(std::isnan(t[s])) << name << " z0 " << z0[cell] << " sample " << s
                                      << " (breakdown during step " << n << ") reads " << t[s];
    }
    if (n == 0) {  // q = p = 0 exactly, z decays monotonically towards 0 (u decreases)
      EXPECT_EQ(r["final_q"][cell], 0.0);
      EXPECT_EQ(r["final_p"][cell], 0.0);
      EXPECT_LE(std::fabs(r["final_z"][cell]), std::fabs(z0[cell]));
    }
  }
}

}  // namespace
}  // namespace cs
