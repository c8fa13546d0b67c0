// λ₁ at fixed points of built-in scenes (engine/fixed_point_exponent.hpp) against the
// eigenvalues of the linearised flow in closed form: q'' + γ q' + V''(q*) q = 0 has exponents
// (−γ ± √(γ² − 4V''))/2, so −γ/2 in a well that rings, (−γ + √(γ² − 4V''))/2 in one that does
// not, and the positive root on a saddle (V'' < 0).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/fixed_point_exponent.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

// The exponent at (q.., p.., z) of `scene` with `params` (catalog order), through a real plan.
double exponent(const std::string& scene, const std::vector<double>& params,
                const std::vector<double>& state) {
  const std::string text = "[scene]\nname = \"" + scene +
                           "\"\n[integrator]\nh = 0.01\nt_end = 1.0\n[grid]\nz_0 = { values = [0.0] }\n"
                           "[measures]\nfinal_state = true\n";
  const RunSpec spec = parse_run_spec(text, {}, "test spec");
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  return fixed_point_exponent(plan, params, state);
}

// Central differences of exact partials: ~1e-10 absolute on these O(1) entries.
constexpr double kTolerance = 1e-8;

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

}  // namespace
}  // namespace cs
