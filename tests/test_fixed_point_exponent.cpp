// λ₁ at fixed points (engine/fixed_point_exponent.hpp) against the eigenvalues of the
// linearised flow in closed form: q'' + γ q' + V''(q*) q = 0 has exponents (−γ ± √(γ² − 4V''))/2,
// so −γ/2 in a well that rings, (−γ + √(γ² − 4V''))/2 in one that does not, and the positive
// root on a saddle (V'' < 0). The Jacobian's entries are the doubles nearest their exact values,
// so the exponents are exact to the eigen solver's rounding; a built-in scene and the same K
// written in the spec give the same bits (one Jacobian, from K's formula).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/fixed_point_exponent.hpp"
#include "engine/run_plan.hpp"
#include "formula/custom_scene.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

// The exponent at (q.., p.., z) of the spec's scene (`scene_lines`) with `params` (its order),
// through a real plan.
double exponent_of(const std::string& scene_lines, const std::vector<double>& params,
                   const std::vector<double>& state) {
  const std::string text = "[scene]\n" + scene_lines +
                           "\n[integrator]\nh = 0.01\nt_end = 1.0\n[grid]\nz_0 = { values = [0.0] }\n"
                           "[measures]\nfinal_state = true\n";
  const RunSpec spec = parse_run_spec(text, {}, "test spec");
  const RunPlan plan(spec, scene_of(spec), *find_method(spec.method));
  return fixed_point_exponent(plan, params, state);
}

double exponent(const std::string& scene, const std::vector<double>& params,
                const std::vector<double>& state) {
  return exponent_of("name = \"" + scene + "\"", params, state);
}

// Exact Jacobian entries of size O(1..10): the eigenvalues to a few ulp of its norm.
constexpr double kTolerance = 1e-14;

TEST(FixedPointExponent, DampedOscillatorIsMinusHalfGamma) {
  EXPECT_NEAR(exponent("damped_oscillator", {1.0, 0.1}, {0.0, 0.0, 1.0}), -0.05, kTolerance);
  EXPECT_NEAR(exponent("damped_oscillator", {2.5, 0.4}, {0.0, 0.0, -3.0}), -0.2, kTolerance);
}

TEST(FixedPointExponent, DoubleWellMinimaRingingAndOverdamped) {
  // V = (q² − a²)²/2: V''(±a) = 4a².
  EXPECT_NEAR(exponent("double_well", {1.0, 0.1}, {1.0, 0.0, 1.0}), -0.05, kTolerance);
  EXPECT_NEAR(exponent("double_well", {1.0, 0.1}, {-1.0, 0.0, 1.0}), -0.05, kTolerance);
  const double gamma = 5.0, curvature = 4.0;  // γ² > 4V'': two real roots, −1 and −4
  EXPECT_NEAR(exponent("double_well", {1.0, gamma}, {1.0, 0.0, 1.0}),
              0.5 * (-gamma + std::sqrt(gamma * gamma - 4.0 * curvature)), kTolerance);
}

TEST(FixedPointExponent, DoubleWellSaddleIsUnstable) {
  // V''(0) = −2a²: the positive root (−γ + √(γ² + 8a²))/2.
  const double a = 1.3, gamma = 0.2;
  EXPECT_NEAR(exponent("double_well", {a, gamma}, {0.0, 0.0, 1.0}),
              0.5 * (-gamma + std::sqrt(gamma * gamma + 8.0 * a * a)), kTolerance);
}

TEST(FixedPointExponent, CoupledOscillatorsTwoDegreesOfFreedom) {
  // At the origin the coupling g q1² q2² has no second derivative: two damped oscillators.
  EXPECT_NEAR(exponent("coupled_oscillators", {1.2, 0.8, 0.8, 0.01}, {0.0, 0.0, 0.0, 0.0, 1.0}),
              -0.005, kTolerance);
}

TEST(FixedPointExponent, ZSquaredDampingCountsZ) {
  // K = p²/2 + ω²q²/2 − γz²: z feeds back (K_z = −2γz), so the state is (q, p, z). At the
  // origin with z = 0: q' = p, p' = −ω²q − 2γzp, z' = K − pK_p = −p²/2 + ω²q²/2 − γz², whose
  // Jacobian there is [[0, 1, 0], [−ω², 0, 0], [0, 0, 0]]: exponents ±iω and 0, so λ₁ = 0.
  // With z = z0 ≠ 0, p' = −ω²q − 2γz0 p and z' has −2γz0 on its diagonal: −γz0 (rings) from the
  // (q, p) block and −2γz0 from z; λ₁ = max(−γz0, −2γz0).
  EXPECT_NEAR(exponent("z2_damping", {1.0, 0.1}, {0.0, 0.0, 0.0}), 0.0, kTolerance);
  EXPECT_NEAR(exponent("z2_damping", {1.0, 0.1}, {0.0, 0.0, 0.5}), -0.05, kTolerance);
}

// A K in the spec and its built-in twin: one Jacobian from one formula, the same bits; the
// parameters come in each scene's own order (the spec's K sorts them by name).
TEST(FixedPointExponent, KWrittenInTheSpecIsTheBuiltInBitForBit) {
  const double builtin = exponent("double_well", {1.3, 0.2}, {1.3, 0.0, 1.0});
  const double as_k = exponent_of("K = \"p^2/2 + (q^2 - a*a)^2/2 - gamma*z\"\na = 1.3\ngamma = 0.2",
                                  {1.3, 0.2}, {1.3, 0.0, 1.0});
  EXPECT_EQ(builtin, as_k);
  EXPECT_NEAR(as_k, -0.1, kTolerance);
  const double saddle = exponent_of("K = \"p^2/2 + (q^2 - a*a)^2/2 - gamma*z\"\na = 1.3\ngamma = 0.2",
                                    {1.3, 0.2}, {0.0, 0.0, 1.0});
  EXPECT_EQ(saddle, exponent("double_well", {1.3, 0.2}, {0.0, 0.0, 1.0}));
  // coupled_oscillators' catalog order is omega1_sq, omega2_sq, g, gamma; the K's is sorted:
  // g, gamma, omega1_sq, omega2_sq.
  const double coupled = exponent_of(
      "K = \"p1^2/2 + p2^2/2 + 0.5*(omega1_sq*q1^2) + 0.5*(omega2_sq*q2^2) + g*(q1^2*q2^2) - "
      "gamma*z\"\nomega1_sq = 1.2\nomega2_sq = 0.8\ng = 0.8\ngamma = 0.01",
      {0.8, 0.01, 1.2, 0.8}, {0.0, 0.0, 0.0, 0.0, 1.0});
  EXPECT_EQ(coupled, exponent("coupled_oscillators", {1.2, 0.8, 0.8, 0.01}, {0.0, 0.0, 0.0, 0.0, 1.0}));
}

// A 2-dof K with no built-in twin: the magnetic pendulum's well under one magnet, against the
// closed form from the Hessian of V, whose eigenvalues k1, k2 give exponents −γ/2 (both ring).
TEST(FixedPointExponent, KWithTwoDegreesOfFreedomRings) {
  // V = w²|q|²/2 − 1/√(|q − m|² + d²) with one magnet m = (1, 0): the fixed point on the axis,
  // where V' = 0: w² q + (q − 1)/r³ = 0, r² = (q − 1)² + d²; V'' = w² + 1/r³ − 3(q − 1)²/r⁵
  // along the axis, w² + 1/r³ across it, both > γ²/4 here (37 and 37.4): λ₁ = −γ/2.
  const double w = 0.5, d = 0.3, gamma = 0.2;
  double q = 1.0;
  for (int i = 0; i < 60; ++i) {  // Newton on V'(q) = 0
    const double u = q - 1.0, r2 = u * u + d * d, r = std::sqrt(r2);
    const double f = w * w * q + u / (r2 * r), df = w * w + (1.0 / (r2 * r) - 3.0 * u * u / (r2 * r2 * r));
    q -= f / df;
  }
  const double lambda = exponent_of(
      "K = \"(p1^2 + p2^2)/2 + w^2*(q1^2 + q2^2)/2 - 1/sqrt((q1 - 1)^2 + q2^2 + d^2) - gamma*z\"\n"
      "w = 0.5\nd = 0.3\ngamma = 0.2",
      {d, gamma, w}, {q, 0.0, 0.0, 0.0, 1.0});
  EXPECT_NEAR(lambda, -gamma / 2, 1e-12);
}

// A cotangent lift K = p·F(q) (van der Pol, Lorenz as K): the Jacobian at (q*, p = 0) is
// [[DF, 0], [·, −DFᵀ]]; p carries the adjoint, whose exponents are the q system's negated. λ₁ is
// the q system's (as the orbit's tangent, seeded in q alone there, measures it), not the largest
// of ±its spectrum: a stable point of F would read as unstable.
TEST(FixedPointExponent, CotangentLiftTakesTheQSystemsExponents) {
  // q1' = q2, q2' = −w2 q1 − g q2: overdamped, (−g ± √(g² − 4w2))/2 = −0.38 and −2.62; the
  // adjoint's +2.62 must not be λ₁. Parameters sorted: g, w2.
  const double g = 3.0, w2 = 1.0;
  EXPECT_NEAR(exponent_of("K = \"p1*q2 + p2*(-w2*q1 - g*q2)\"\ng = 3.0\nw2 = 1.0", {g, w2},
                          {0.0, 0.0, 0.0, 0.0, 0.0}),
              0.5 * (-g + std::sqrt(g * g - 4.0 * w2)), kTolerance);
  // Lorenz at r = 10 < r_H: C± = (±√(b(r−1)), ±√(b(r−1)), r−1) attract. The characteristic
  // polynomial λ³ + (s+b+1)λ² + b(s+r)λ + 2bs(r−1) has one real root ρ (Newton from −s−b−1)
  // and a complex pair whose real part is (−(s+b+1) − ρ)/2 by the trace: λ₁ = that part.
  const double s = 10.0, r = 10.0, b = 8.0 / 3.0;
  double rho = -(s + b + 1.0);
  for (int i = 0; i < 50; ++i) {
    const double f = ((rho + s + b + 1.0) * rho + b * (s + r)) * rho + 2.0 * b * s * (r - 1.0);
    const double df = (3.0 * rho + 2.0 * (s + b + 1.0)) * rho + b * (s + r);
    rho -= f / df;
  }
  const double pair = 0.5 * (-(s + b + 1.0) - rho);
  ASSERT_GT(pair, rho);  // the pair's real part is the largest, and < 0: C± attract
  ASSERT_LT(pair, 0.0);
  const double c = std::sqrt(b * (r - 1.0));
  const std::string lorenz =
      "K = \"p1*(s*(q2 - q1)) + p2*(q1*(r - q3) - q2) + p3*(q1*q2 - b*q3)\"\n"
      "s = 10.0\nr = 10.0\nb = 2.6666666666666665";
  // Parameters sorted: b, r, s. Entries of size up to 13: a few ulp of that.
  for (const double sign : {1.0, -1.0})
    EXPECT_NEAR(exponent_of(lorenz, {b, r, s}, {sign * c, sign * c, r - 1.0, 0.0, 0.0, 0.0, 0.0}),
                pair, 1e-13);
}

}  // namespace
}  // namespace cs
