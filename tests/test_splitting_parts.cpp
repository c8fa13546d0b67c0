// What the splitting methods and the symmetric leap-frog rest on, checked piece by piece (the
// methods' accuracy as a whole: test_methods.cpp): each splittable scene is the sum of the parts
// split_flows.hpp reads off K, the composition tables are symmetric and consistent, and the
// symmetric leap-frog's two Newton steps solve its trapezoidal z update to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "numerics/method_list.hpp"
#include "physics/coupled_oscillators.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/double_well.hpp"
#include "physics/z2_damping.hpp"
#include "support/time_dependent_scenes.hpp"

namespace cs {
namespace {

constexpr Carry kAll{true, true};

// ---- what the splitting methods rest on --------------------------------------------------------

// split_flows.hpp reads V, V′ and Z's coefficient off K, assuming K = Σp²/2 + V(q) + Z(z) with Z
// as declared by the scene's z_part: check that decomposition at random states.
template <SplittableScene S>
void expect_sum_of_parts(const ParamsOf<S, double>& c) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 100; ++trial) {
    double q[S::dof], p[S::dof], z = u(rng), t = 3.0 + u(rng);  // t > 0: Lane–Emden's 2/t
    double kinetic = 0.0;
    for (int d = 0; d < S::dof; ++d) q[d] = u(rng), p[d] = u(rng), kinetic += 0.5 * p[d] * p[d];
    const double k = z_coefficient<S>(c, t);
    const double zpart = S::z_part == ZPart::linear ? k * z : k * z * z;
    const double whole = K<S>(q, p, z, c, t), parts = kinetic + potential<S>(q, c, t) + zpart;
    // Terms of size ≲ 30 summed in a different order: a few ulps of 30.
    EXPECT_NEAR(whole, parts, 1e-13) << "trial " << trial;
    double v, force;
    potential_and_force<S, 0>(q, c, t, v, force);
    EXPECT_EQ(force, (K_q<S, 0>(q, p, z, c, t)));  // K_q ignores p and z: separable
  }
}

TEST(SplitParts, EachSplittableSceneIsTheSumOfItsParts) {
  expect_sum_of_parts<DampedOscillator>({1.3, 0.2});
  expect_sum_of_parts<Z2Damping>({1.3, 0.2});
  expect_sum_of_parts<DoubleWell>({0.8, 0.2});
  expect_sum_of_parts<CoupledOscillators>({1.2, 0.8, 0.7, 0.05});
  expect_sum_of_parts<test::ForcedOscillator>({1.0, 0.1, 0.5, 1.3});
  expect_sum_of_parts<test::LaneEmden5>({0.0});
  EXPECT_EQ(z_coefficient<Z2Damping>(ParamsOf<Z2Damping, double>{1.0, 0.2}, 0.0), -0.2);
  EXPECT_EQ(z_coefficient<DampedOscillator>(ParamsOf<DampedOscillator, double>{1.0, 0.2}, 0.0),
            -0.2);
  EXPECT_EQ(z_coefficient<test::LaneEmden5>(ParamsOf<test::LaneEmden5, double>{0.0}, 4.0), -0.5);
}

// Σw = 1 (consistency) and Σw³ = 0 (the order-3 error of symmetric S₂'s cancels), to round-off
// of the printed coefficients (15 digits for Yoshida's solution A).
template <class Composition>
void expect_consistent_composition(double tolerance) {
  double sum = 0.0, cubes = 0.0;
  const auto& w = Composition::weights;
  for (std::size_t s = 0; s < w.size(); ++s) {
    sum += w[s];
    cubes += w[s] * w[s] * w[s];
    EXPECT_EQ(w[s], w[w.size() - 1 - s]) << "not palindromic";
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  if (ContactSplitting<Composition>::order >= 4) {
    EXPECT_NEAR(cubes, 0.0, tolerance);
  }
}

TEST(ContactSplitting, CompositionTablesAreSymmetricAndConsistent) {
  expect_consistent_composition<StrangComposition>(0.0);
  expect_consistent_composition<YoshidaComposition4>(1e-15);
  expect_consistent_composition<YoshidaComposition6>(1e-14);
}

// ---- the symmetric leap-frog's implicit z update -----------------------------------------------

// One step on scene B (K_z = −2γz) against the scheme written out with λ itself and the
// trapezoid's quadratic in z¹ solved in closed form: the two fixed Newton steps must reach it to
// round-off over the range symmetric_leapfrog.hpp states (h ≤ 0.1, γ ≤ 0.2, |z| ≲ 2).
void expect_step_solves_the_trapezoid(double h, double gamma, double z0) {
  SCOPED_TRACE("h " + std::to_string(h) + " gamma " + std::to_string(gamma) + " z0 " +
               std::to_string(z0));
  const double omega = 1.1, q0 = 0.7, p0 = -0.4, lambda0 = 1.3;
  const double hh = 0.5 * h;
  auto Kz = [&](double z) { return -2.0 * gamma * z; };
  auto R = [&](double q, double p, double z) {  // K − pK_p
    return 0.5 * (omega * omega * q * q - p * p) - gamma * z * z;
  };
  const double a = 1.0 + hh * Kz(z0);
  const double lambda_half = lambda0 / a;
  const double p_half = a * p0 - hh * omega * omega * q0;
  const double q1 = q0 + h * p_half;
  // z¹ = z⁰ + hh(R⁰ + R(q¹, p½, 0) − γz¹²): hh·γ·z¹² + z¹ − rhs = 0 with
  // rhs = z⁰ + hh(R⁰ + R(q¹, p½, 0)); the root near z⁰, written without cancellation:
  const double rhs = z0 + hh * (R(q0, p_half, z0) + R(q1, p_half, 0.0));
  const double z1 = 2.0 * rhs / (1.0 + std::sqrt(1.0 + 4.0 * hh * gamma * rhs));
  const double b = 1.0 - hh * Kz(z1);
  const double lambda1 = lambda_half * b;
  const double p1 = (p_half - hh * omega * omega * q1) / b;

  ParamsOf<Z2Damping, double> c{omega, gamma};
  LaneState<1> x{};
  x.q[0] = q0, x.p[0] = p0, x.z = z0, x.mu = std::log(lambda0);
  SymmetricLeapfrog::start<Z2Damping>(x, c);
  const auto k = SymmetricLeapfrog::coefficients<Z2Damping>(h, c, x);
  SymmetricLeapfrog::step<Z2Damping, kAll>(x, c, k);
  // Newton's error after two steps is ≲ 1e-17 at h = 0.1, |z| ~ 1 (symmetric_leapfrog.hpp);
  // what remains is a few ulps from a different association of the same products.
  const double ulp = 2.3e-16;  // 2^-52 is 2.2e-16
  EXPECT_NEAR(x.z, z1, 4 * ulp * std::max(1.0, std::fabs(z1)));
  EXPECT_NEAR(x.q[0], q1, 4 * ulp);
  EXPECT_NEAR(x.p[0], p1, 4 * ulp);
  EXPECT_NEAR(x.mu, std::log(lambda1), 4 * ulp * std::max(1.0, std::fabs(std::log(lambda1))));
  EXPECT_EQ(x.broken, 0.0);
}

TEST(SymmetricLeapfrog, OneStepSolvesTheTrapezoidOnSceneB) {
  for (double h : {0.01, 0.05, 0.1})
    for (double gamma : {0.1, 0.2})
      for (double z0 : {-1.0, 0.9, 2.0}) expect_step_solves_the_trapezoid(h, gamma, z0);
}

}  // namespace
}  // namespace cs
