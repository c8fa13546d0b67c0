// Where a basin map's fixed point may take λ₁ from the Jacobian (engine/attractor_analysis.hpp)
// and where it must not: the table holds q and p alone, and the Jacobian is taken at the
// source lane's initial z and at t_start. That is the fixed point's linearisation only where
// z does not feed back (z is then no part of the (q, p) flow) and K does not read t. Elsewhere
// the attractor is described by its orbit, as any other, and the orbit's λ₁ is the value.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/attractor_analysis.hpp"
#include "engine/attractor_table.hpp"
#include "engine/fixed_point_exponent.hpp"
#include "engine/run_plan.hpp"
#include "formula/custom_scene.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"

namespace cs {
namespace {

// A value no Jacobian gives here: the stub orbit's, so the test sees which one was used.
constexpr double kOrbitLyapunov = -0.123456789;

void stub_orbit(const OrbitRequest& request, AttractorOrbit& out) {
  out.points.assign(static_cast<std::size_t>(request.samples) * 2, 0.0);
  out.lyapunov = kOrbitLyapunov;
  out.return_time = std::nan("");
  out.moved = false;
  out.finite = true;
}

struct Described {
  bool needs_orbit;
  AttractorAnalysis analysis;
};

// The map's one fixed point at the origin (q, p) = (0, 0), its source lane the grid's first,
// which starts at z = z0.
Described describe(const std::string& scene_lines, double z0) {
  const std::string text = "[scene]\n" + scene_lines +
                           "\n[initial]\nz = " + std::to_string(z0) +
                           "\n[integrator]\nmethod = \"rk4\"\nh = 0.01\nt_end = 100.0\n"
                           "[grid]\nq_0 = { from = -1.0, to = 1.0, n = 4 }\n"
                           "[measures]\nbasin = {}\n";
  const RunSpec spec = parse_run_spec(text, {}, "test spec");
  const RunPlan plan(spec, scene_of(spec), *find_method(spec.method));
  Attractor a;
  a.label = 1;
  a.period = 1;
  a.point = {0.0, 0.0};
  a.source = 0;
  const std::vector<Attractor> table{a};
  const bool needs = needs_orbits(plan, table);
  const auto analysis =
      analyse_attractors(plan, table, needs ? &stub_orbit : nullptr, &fixed_point_exponent);
  return {needs, analysis.at(0)};
}

TEST(FixedPointScope, LinearDampingTakesTheJacobian) {
  // K = p²/2 + q²/2 − g z, g = 3: (−3 + √5)/2, with no orbit.
  const Described d = describe("K = \"p^2/2 + q^2/2 - g*z\"\ng = 3.0", 0.3);
  EXPECT_FALSE(d.needs_orbit);
  EXPECT_EQ(d.analysis.kind, AttractorKind::fixed_point);
  EXPECT_NEAR(d.analysis.lyapunov, 0.5 * (-3.0 + std::sqrt(5.0)), 1e-14);
}

TEST(FixedPointScope, ZThatFeedsBackIsDescribedByTheOrbit) {
  // K = p²/2 + q²/2 + c − γz²: at (0, 0) z' = c − γz², so the fixed point is (0, 0, √(c/γ)),
  // where λ₁ = −γ√(c/γ) = −0.316; the Jacobian at the lane's initial z = 0.3 gives −γ·0.3 = −0.06.
  const Described d = describe("K = \"p^2/2 + q^2/2 + c - gamma*z^2\"\nc = 0.5\ngamma = 0.2", 0.3);
  EXPECT_TRUE(d.needs_orbit);
  EXPECT_EQ(d.analysis.kind, AttractorKind::fixed_point);
  EXPECT_EQ(d.analysis.lyapunov, kOrbitLyapunov);
}

TEST(FixedPointScope, KThatReadsTimeIsDescribedByTheOrbit) {
  // K = p²/2 + (1 + e^−t) q²/2 − g z, g = 3: the stiffness relaxes from 2 to 1, so the lanes
  // approach the origin at (−3 + √5)/2 = −0.38, while the Jacobian at t_start = 0 says −1.
  const Described d = describe("K = \"p^2/2 + (1 + exp(-t))*q^2/2 - g*z\"\ng = 3.0", 0.0);
  EXPECT_TRUE(d.needs_orbit);
  EXPECT_EQ(d.analysis.kind, AttractorKind::fixed_point);
  EXPECT_EQ(d.analysis.lyapunov, kOrbitLyapunov);
}

}  // namespace
}  // namespace cs
