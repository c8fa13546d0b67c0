// dop853's dense output (numerics/dop853_dense.hpp) and the trajectory it samples: the
// continuous extension's order 7 on one step of scene A, the engine's samples against scene A's
// closed form within a multiple of the tolerance, the steps unchanged by sampling, and the same
// bits for any cut of the grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "numerics/dop853_dense.hpp"
#include "numerics/methods/dop853.hpp"
#include "physics/damped_oscillator.hpp"
#include "support/exact_damped_oscillator.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

using S = DampedOscillator;
const ParamsOf<S, double> kSceneA{1.0, 0.1};  // ω = 1, γ = 0.1 (the paper's scene A)
using Dense = Dop853Dense<S, false, false>;
using P = Dense::P;

// One step of h from (q, p) = (1, 0) at t = 0 and its continuous extension.
Dense one_step(double h) {
  LaneState<1> x{};
  x.q[0] = 1.0, x.p[0] = 0.0, x.z = 1.0;
  const P y0{x};
  P r[12];
  contact_field::unrolled<12>([&](auto i) {
    r[i] = Dop853::stage<decltype(i)::value, S, false, false>(y0, kSceneA, 0.0, h, r);
  });
  Dop853::step<S, Carry{false, false}>(x, kSceneA, Dop853::Coef<double>{h});
  return Dense::build(y0, P{x}, r, kSceneA, 0.0, h);
}

// The largest error of the extension at θ = 1/4, 1/2, 3/4 of the step against the closed form.
double interpolation_error(double h) {
  const Dense d = one_step(h);
  double worst = 0.0;
  for (double theta : {0.25, 0.5, 0.75}) {
    const P y = d.at_time(theta * h);
    const test::ExactState e = test::exact_damped_oscillator(theta * h, 1.0, 0.1, 1.0, 0.0, 1.0, 1.0);
    worst = std::max(worst, std::hypot(y.q[0] - e.q, y.p[0] - e.p));
  }
  return worst;
}

// The extension is of order 7: inside a step its error is O(h⁸) (Hairer–Wanner II.6), so
// halving h divides it by 2⁸. From h = 0.8 to 0.4 to 0.2 the errors stay far above round-off.
TEST(Dop853Dense, InterpolationErrorScalesAsTheSeventhOrderExtensionPromises) {
  std::vector<double> errors;
  for (double h : {0.8, 0.4, 0.2}) errors.push_back(interpolation_error(h));
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1] / errors[i]);
    EXPECT_NEAR(order, 8.0, 0.5) << "errors " << errors[i - 1] << " " << errors[i];
    std::printf("interpolation error %.3g -> %.3g: order %.2f\n", errors[i - 1], errors[i], order);
  }
  EXPECT_GT(errors.back(), 1e-14);  // the slope is the formula's, not round-off's
}

// At the step's ends the extension is the step's endpoints: y0 exactly (θ = 0), y1 to rounding.
TEST(Dop853Dense, MeetsTheStepsEndpoints) {
  const Dense d = one_step(0.5);
  const P a = d.at_time(0.0), b = d.at_time(0.5);
  EXPECT_EQ(a.q[0], d.y0.q[0]);
  EXPECT_EQ(a.p[0], d.y0.p[0]);
  EXPECT_NEAR(b.q[0], d.y1.q[0], 4e-16);
  EXPECT_NEAR(b.p[0], d.y1.p[0], 4e-16);
}

// A grid of scene A with a trajectory every 50 nominal steps of h = 0.01 (every 0.5 in time) to
// t_end = 20: 41 samples, each interpolated inside a lane's own step.
std::string trajectory_spec(const std::string& rtol, bool trajectory = true) {
  return R"(
  [scene]
  name = "damped_oscillator"
  [integrator]
  method = "dop853"
  rtol = )" + rtol + R"(
  h = 0.01
  t_end = 20.0
  [grid]
  q_0 = { from = -1.0, to = 1.0, n = 9 }
  p_0 = { from = -1.0, to = 1.0, n = 7 }
  [measures]
  final_state = true
  )" + (trajectory ? "trajectory = { every = 50 }" : "");
}
constexpr int kPoints = 9 * 7, kSamples = 41;

// The largest error of any sample of q, p and ln λ against the closed form (the initial values
// read off sample 0). Not z: on scene A z is a passenger, outside the error norm
// (numerics/methods/dop853.hpp), so rtol does not bound it (the lane at q = p = 0 has no error
// to control and steps to h_max = t_end).
double worst_sample_error(const test::Datasets& r) {
  const auto &q = r.at("traj_q"), &p = r.at("traj_p"), &z = r.at("traj_z");
  const auto& mu = r.at("traj_log_lambda");
  EXPECT_EQ(q.size(), std::size_t{kPoints} * kSamples);
  double worst = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const std::size_t at0 = static_cast<std::size_t>(k) * kSamples;
    for (int s = 0; s < kSamples; ++s) {
      const std::size_t at = at0 + s;
      const test::ExactState e = test::exact_damped_oscillator(
          0.5 * s, 1.0, 0.1, q[at0], p[at0], z[at0], std::exp(mu[at0]));
      EXPECT_TRUE(std::isfinite(q[at]) && std::isfinite(p[at])) << "point " << k << " sample " << s;
      worst = std::max({worst, std::fabs(q[at] - e.q), std::fabs(p[at] - e.p),
                        std::fabs(mu[at] - e.log_lambda)});
    }
  }
  return worst;
}

// Every sample is within a multiple of rtol of the closed form (the global error is ∝ rtol,
// test_dop853.cpp, and the extension's own error is below the step's tolerance), and the
// error falls with rtol: three decades of rtol, at least two of error.
TEST(Dop853Dense, TrajectorySamplesMatchTheClosedFormWithinTheTolerance) {
  const double loose = worst_sample_error(test::run_in_memory(trajectory_spec("1e-7")));
  const double tight = worst_sample_error(test::run_in_memory(trajectory_spec("1e-10")));
  std::printf("worst sample error: %.3g at rtol 1e-7, %.3g at rtol 1e-10\n", loose, tight);
  EXPECT_LT(loose, 20 * 1e-7);
  EXPECT_LT(tight, 20 * 1e-10);
  EXPECT_GT(loose / tight, 100.0) << loose << " " << tight;
}

// Sampling reads the steps, it does not change them: final states the same bits as a run
// without trajectory; and the samples the same bits for any cut of the grid.
TEST(Dop853Dense, SamplingLeavesTheStepsAloneAndAnyCutGivesTheSameBits) {
  const std::string spec = trajectory_spec("1e-8");
  const test::Datasets whole = test::run_in_memory(spec);
  const test::Datasets plain = test::run_in_memory(trajectory_spec("1e-8", false));
  auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  };
  for (const char* name : {"final_q", "final_p"}) EXPECT_TRUE(same(whole.at(name), plain.at(name))) << name;
  for (std::int64_t block : {1, 10, 40}) {
    const test::Datasets cut = test::run_in_memory(spec, {}, block);
    for (const char* name : {"traj_q", "traj_p", "traj_z", "traj_log_lambda", "traj_H", "final_q"})
      EXPECT_TRUE(same(whole.at(name), cut.at(name))) << name << " block " << block;
  }
}

// Sync with dop853: its samples at the looks' nominal times (every 32 h = 0.16 here), each
// interpolated inside the lane's step, give the fixed-step reference's sync_* (rk4 at the same
// h: its global error ~10⁻⁸ at t = 40) to 10⁻⁶, over couplings from none to strong; the same
// bits for any cut of the grid.
TEST(Dop853Dense, SyncMatchesTheFixedStepReference) {
  const std::string spec = R"(
  [scene]
  name = "coupled_oscillators"
  omega1_sq = 1.2
  omega2_sq = 0.8
  [initial]
  q1 = 1.0
  q2 = -1.0
  [integrator]
  h = 0.005
  t_end = 40.0
  [grid]
  g = { from = 0.0, to = 1.0, n = 3 }
  gamma = { from = 0.0, to = 0.05, n = 2 }
  [measures]
  sync = { window = [10.0, 40.0] })";
  const test::Datasets ref = test::run_in_memory(spec, {"integrator.method=\"rk4\""});
  const test::Datasets ad = test::run_in_memory(
      spec, {"integrator.method=\"dop853\"", "integrator.rtol=1e-10"});
  double worst = 0.0;
  for (const char* name : {"sync_r", "sync_phase_drift", "sync_freq_ratio", "sync_amplitude"}) {
    const std::vector<double>&a = ref.at(name), &b = ad.at(name);
    ASSERT_EQ(a.size(), 6u);
    ASSERT_EQ(b.size(), 6u);
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_TRUE(std::isfinite(b[k])) << name << " " << k;
      EXPECT_NEAR(a[k], b[k], 1e-6) << name << " " << k;
      worst = std::max(worst, std::fabs(a[k] - b[k]));
    }
  }
  std::printf("sync_*: largest difference from rk4 %.3g\n", worst);
  // Each lane's samples are its own: the same bits for any cut of the grid.
  for (std::int64_t block : {1, 4}) {
    const test::Datasets cut = test::run_in_memory(
        spec, {"integrator.method=\"dop853\"", "integrator.rtol=1e-10"}, block);
    for (const char* name : {"sync_r", "sync_phase_drift", "sync_freq_ratio", "sync_amplitude"})
      EXPECT_EQ(0, std::memcmp(ad.at(name).data(), cut.at(name).data(), 6 * sizeof(double)))
          << name << " block " << block;
  }
}

}  // namespace
}  // namespace cs
