// The hybrid leap-frog against the paper's formulas, the exact solution of scene A, and the
// H = λK drift law of shared/PHYSICS.md.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "numerics/hybrid_leapfrog.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/z2_damping.hpp"
#include "support/format_number.hpp"

namespace cs {
namespace {

constexpr Carry kAll{true, true};

template <class S>
LaneState<S::dof> lane(std::initializer_list<double> q, std::initializer_list<double> p, double z,
                       double lambda, const ParamsOf<S, double>& c) {
  LaneState<S::dof> x{};
  std::copy(q.begin(), q.end(), x.q);
  std::copy(p.begin(), p.end(), x.p);
  x.z = z;
  x.mu = std::log(lambda);
  HybridLeapfrog::start<S>(x, c);
  return x;
}

// One step of scene B (state-dependent K_z, z feeds back) written out from the paper's
// sequential procedure (sec. 3.1) with λ itself, not ln λ.
TEST(HybridLeapfrog, OneStepEqualsThePapersFormulas) {
  const double omega = 1.1, gamma = 0.2, h = 0.05;
  const double q0 = 0.7, p0 = -0.4, z0 = 0.9, lambda0 = 1.3;
  auto Kz = [&](double z) { return -2.0 * gamma * z; };
  auto Kq = [&](double q) { return omega * omega * q; };
  auto Kp = [&](double p) { return p; };
  auto zrate = [&](double q, double p, double z) {
    return 0.5 * (omega * omega * q * q - p * p) - gamma * z * z;  // K − pK_p
  };
  double lambda_h = lambda0 * (1 - h / 2 * Kz(z0));
  double p_h = (lambda0 / lambda_h) * (p0 - h / 2 * Kq(q0));
  double z_h = z0 + h / 2 * zrate(q0, p0, z0);  // appended predictors
  double q_h = q0 + h / 2 * Kp(p0);
  double z1 = z0 + h * zrate(q_h, p_h, z_h);
  double q1 = q0 + h * Kp(p_h);
  double lambda1 = lambda_h / (1 + h / 2 * Kz(z1));
  double p1 = (lambda_h / lambda1) * p_h - h / 2 * Kq(q1);

  ParamsOf<Z2Damping, double> c{omega, gamma};
  auto x = lane<Z2Damping>({q0}, {p0}, z0, lambda0, c);
  auto k = HybridLeapfrog::coefficients<Z2Damping>(h, c, x);
  HybridLeapfrog::step<Z2Damping, kAll>(x, c, k);
  // Same formulas, different association of a few products: a few ulps.
  EXPECT_NEAR(x.q[0], q1, 1e-15);
  EXPECT_NEAR(x.p[0], p1, 1e-15);
  EXPECT_NEAR(x.z, z1, 1e-15);
  EXPECT_NEAR(x.mu, std::log(lambda1), 1e-15);
  EXPECT_EQ(x.broken, 0.0);
}

// Its order (2.00 in q, p, z and ln λ on the exact scene A) is checked with every other
// method's in test_methods.cpp.

// PHYSICS.md: the relative error of H drifts linearly at −γh²ω²⟨λE⟩/(8H) per unit time.
// γ = 0.01 keeps γt = 100 at t = 10⁴, far from underflow.
TEST(HybridLeapfrog, HDriftsLinearlyAtThePredictedRate) {
  const double omega = 1.0, gamma = 0.01, h = 0.01;
  ParamsOf<DampedOscillator, double> c{omega, gamma};
  auto x = lane<DampedOscillator>({1.0}, {0.0}, 1.0, 1.0, c);
  auto k = HybridLeapfrog::coefficients<DampedOscillator>(h, c, x);
  auto H = [&] { return std::exp(x.mu) * K<DampedOscillator>(x.q, x.p, x.z, c); };
  const double H0 = H();
  double sum_lambda_E = 0.0;
  std::vector<double> drift;  // relative error of H at t = 2500, 5000, 7500, 10000
  const long steps = 1000000;
  for (long n = 1; n <= steps; ++n) {
    HybridLeapfrog::step<DampedOscillator, kAll>(x, c, k);
    sum_lambda_E += std::exp(x.mu) * 0.5 * (x.p[0] * x.p[0] + omega * omega * x.q[0] * x.q[0]);
    if (n % 250000 == 0) drift.push_back(H() / H0 - 1.0);
  }
  double mean_lambda_E = sum_lambda_E / steps;
  double predicted_rate = -gamma * h * h * omega * omega * mean_lambda_E / (8.0 * H0);
  double measured_rate = drift.back() / 1e4;
  RecordProperty("measured_rate", test::full_precision(measured_rate));
  // The law is the leading term of a modified-equation expansion; oscillating terms of
  // relative size O(h) and the O(γ) variation of λE over a period stay far below 5 %.
  EXPECT_NEAR(measured_rate / predicted_rate, 1.0, 0.05);
  for (std::size_t i = 0; i < drift.size(); ++i)  // linear, not bounded or quadratic
    EXPECT_NEAR(drift[i] / drift.back(), (i + 1) / 4.0, 0.02);
}

TEST(HybridLeapfrog, LogLambdaStaysFiniteAndExactToTenThousand) {
  const double gamma = 0.1, h = 0.01;
  ParamsOf<DampedOscillator, double> c{1.0, gamma};
  auto x = lane<DampedOscillator>({1.0}, {0.0}, 1.0, 1.0, c);
  auto k = HybridLeapfrog::coefficients<DampedOscillator>(h, c, x);
  for (long n = 0; n < 1000000; ++n) HybridLeapfrog::step<DampedOscillator, kAll>(x, c, k);
  // λ = e^{1000} would have overflowed near t = 7100; ln λ gains ln((1+hγ/2)/(1−hγ/2)) =
  // hγ(1 + (hγ)²/12 + …) per step, summed 10⁶ times (round-off ≲ 10⁶·ulp(1000) ≈ 1e-7).
  ASSERT_TRUE(std::isfinite(x.mu));
  const double expected = gamma * 1e4 * (1.0 + (h * gamma) * (h * gamma) / 12.0);
  EXPECT_NEAR(x.mu, expected, 1e-6);
}

}  // namespace
}  // namespace cs
