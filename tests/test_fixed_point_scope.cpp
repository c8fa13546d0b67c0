// Where a basin map's fixed point may take λ₁ from the Jacobian (engine/attractor_analysis.hpp)
// and where it must not: the table holds q and p alone, and the Jacobian is taken at the
// source lane's initial z and at t_start. That is the fixed point's linearisation only where
// z does not feed back (z is then no part of the (q, p) flow) and K does not read t, and only
// where the Jacobian applies at the table's point: its entries finite there, and the field
// vanishing to within 2·τ·‖J‖∞ (fixed_point_exponent.cpp). Elsewhere the attractor is described
// by its orbit, as any other, and the orbit's λ₁ is the value.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
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

// Where the stub's orbit started, and after how many steps of transient (one attractor: one call).
std::vector<double> orbit_start;
std::int64_t orbit_transient = -1;

void stub_orbit(const OrbitRequest& request, AttractorOrbit& out) {
  orbit_start.assign(request.state.begin(), request.state.begin() + 2);
  orbit_transient = request.transient_steps;
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

// The map's one fixed point at `point` (q, p), by default the origin, its source lane the
// grid's first, which starts at z = z0.
Described describe(const std::string& scene_lines, double z0,
                   const std::vector<double>& point = {0.0, 0.0}) {
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
  a.point = point;
  a.source = 0;
  const std::vector<Attractor> table{a};
  const bool needs = needs_orbits(plan, table, &fixed_point_linearisation);
  orbit_start.clear();
  orbit_transient = -1;
  const auto analysis =
      analyse_attractors(plan, table, needs ? &stub_orbit : nullptr, &fixed_point_linearisation);
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

// A K that is smooth enough at the point but whose partials GiNaC writes in a form that is 0/0
// there: sqrt(q^4) = q² has K_q = 2q³/√(q⁴), and |q|³ has K_qq = 6|q|²/|q|·…, undefined at
// q = 0, where the exact linearisation is the damped oscillator's (V''(0) = 1: λ₁ = −γ/2 =
// −0.125 with γ = 0.25). The Jacobian cannot give it there, and NaN is no exponent: the orbit
// describes the point.
TEST(FixedPointScope, PartialsUndefinedAtThePointAreDescribedByTheOrbit) {
  for (const char* v : {"sqrt(q^4)/2", "q^2/2 + abs(q)^3"}) {
    SCOPED_TRACE(v);
    const Described d = describe(std::string("K = \"p^2/2 + ") + v + " - g*z\"\ng = 0.25", 0.0);
    EXPECT_TRUE(d.needs_orbit);
    EXPECT_EQ(d.analysis.kind, AttractorKind::fixed_point);
    EXPECT_EQ(d.analysis.lyapunov, kOrbitLyapunov);
    // The orbit's own formulas are the same 0/0 at the point: a lane started there breaks down
    // at its first step (NaN). It starts where the source lane did, the grid's first point
    // (q, p) = (−1, 0), which the map integrated to the point, over the whole run as transient
    // (t_end / h = 10⁴ steps), as an attractor found by recurrences does.
    EXPECT_EQ(orbit_start, (std::vector<double>{-1.0, 0.0}));
    EXPECT_EQ(orbit_transient, 10000);
  }
  // GiNaC writes abs(q)^2 as q² for a real q: a Jacobian finite at 0, which keeps its −γ/2.
  const Described d = describe("K = \"p^2/2 + abs(q)^2/2 - g*z\"\ng = 0.25", 0.0);
  EXPECT_FALSE(d.needs_orbit);
  EXPECT_NEAR(d.analysis.lyapunov, -0.125, 1e-15);
}

// V = q²/2 + 0.1|q| with γ = 0.5: rk4's lanes chatter across the kink at q = 0 and the anchor
// test records a point beside it, (1.2·10⁻⁴, −6.2·10⁻³), where the field is no fixed point's:
// p' = −q − 0.1 − γp ≈ −0.097, against the at most 2·‖J‖∞·tolerance = 3·10⁻³ a point within the
// tolerance (10⁻³) of a fixed point can have. The Jacobian there (−γ/2 = −0.25) is no fixed
// point's exponent: the orbit describes it.
TEST(FixedPointScope, PointWhereTheFieldDoesNotVanishIsDescribedByTheOrbit) {
  const std::string k = "K = \"p^2/2 + q^2/2 + 0.1*abs(q) - g*z\"\ng = 0.5";
  for (const double sign : {1.0, -1.0}) {
    const Described d = describe(k, 0.0, {sign * 1.2e-4, -sign * 6.2e-3});
    EXPECT_TRUE(d.needs_orbit);
    EXPECT_EQ(d.analysis.kind, AttractorKind::fixed_point);
    EXPECT_EQ(d.analysis.lyapunov, kOrbitLyapunov);
    // Its formulas are finite there: the lane starts at the point, half the run as transient.
    EXPECT_EQ(orbit_start, (std::vector<double>{sign * 1.2e-4, -sign * 6.2e-3}));
    EXPECT_EQ(orbit_transient, 5000);
  }
}

// The rule's other side: a table point within the tolerance of the fixed point (the anchor
// test's lane is anywhere within it) keeps the exact value. The damped oscillator with
// g = 3 at (q, p) = (0.9, −0.9)·10⁻³ off its fixed point: ‖f‖∞ = 1.8·10⁻³ ≤ 2·‖J‖∞·10⁻³ = 8·10⁻³;
// the Jacobian is constant, so λ₁ = (−3 + √5)/2 exactly as at the origin.
TEST(FixedPointScope, PointWithinTheToleranceKeepsTheJacobian) {
  const Described d = describe("K = \"p^2/2 + q^2/2 - g*z\"\ng = 3.0", 0.3, {0.9e-3, -0.9e-3});
  EXPECT_FALSE(d.needs_orbit);
  EXPECT_NEAR(d.analysis.lyapunov, 0.5 * (-3.0 + std::sqrt(5.0)), 1e-14);
}


// An unstable fixed point is no attractor (attractor_analysis.hpp, unstable_fixed_point): where
// the exact λ₁ applies and exceeds kUnstableMargin·‖J‖∞ the table refuses the point
// (merge_candidates). The map's spec as describe's, over q_0 ∈ {−1, −1/3, 1/3, 1}.
struct Map {
  std::unique_ptr<RunSpec> spec;
  std::unique_ptr<RunPlan> plan;
};

Map map_of(const std::string& scene_lines) {
  Map m;
  m.spec = std::make_unique<RunSpec>(parse_run_spec(
      "[scene]\n" + scene_lines +
          "\n[initial]\nz = 0.0\n[integrator]\nmethod = \"rk4\"\nh = 0.01\nt_end = 100.0\n"
          "[grid]\nq_0 = { from = -1.0, to = 1.0, n = 4 }\n[measures]\nbasin = {}\n",
      {}, "test spec"));
  m.plan = std::make_unique<RunPlan>(*m.spec, scene_of(*m.spec), *find_method(m.spec->method));
  return m;
}

FixedPointLinearisation linearisation_at(const RunPlan& plan, double q, double p) {
  Attractor a;
  a.period = 1;
  a.point = {q, p};
  a.source = 0;
  return linearisation_of(plan, a, &fixed_point_linearisation);
}

TEST(UnstableFixedPoint, SaddleIsRefusedMinimumAndCentreKept) {
  // The damped double well K = p²/2 + (q² − 1)²/2 − g z, g = 0.1: at the saddle q = 0,
  // J_(q,p) = [[0, 1], [2, −g]], λ₁ = (−g + √(g² + 8))/2 = 1.3651; at the minima −g/2.
  const Map well = map_of("K = \"p^2/2 + (q^2 - 1)^2/2 - g*z\"\ng = 0.1");
  Attractor saddle;
  saddle.point = {0.0, 0.0};
  saddle.source = 0;
  const FixedPointLinearisation s = linearisation_at(*well.plan, 0.0, 0.0);
  EXPECT_NEAR(s.lyapunov, 0.5 * (-0.1 + std::sqrt(0.01 + 8.0)), 1e-14);
  // ‖J‖∞ over (q, p, z): the p row |−V''(0)| + |−g| = 2 + 0.1 (docs/basins.md quotes it).
  EXPECT_DOUBLE_EQ(s.norm, 2.1);
  EXPECT_TRUE(unstable_fixed_point(*well.plan, saddle, s));
  Attractor minimum = saddle;
  minimum.point = {1.0, 0.0};
  const FixedPointLinearisation m = linearisation_at(*well.plan, 1.0, 0.0);
  EXPECT_NEAR(m.lyapunov, -0.05, 1e-15);
  EXPECT_FALSE(unstable_fixed_point(*well.plan, minimum, m));
  // A centre of a conservative K (±i): a real part rounding may leave on either side of 0 is
  // far inside the margin, and the point is kept.
  const Map centre = map_of("K = \"p^2/2 + q^2/2\"");
  const FixedPointLinearisation c = linearisation_at(*centre.plan, 0.0, 0.0);
  EXPECT_LE(std::fabs(c.lyapunov), 1e-15);
  EXPECT_GE(c.norm, 1.0);
  EXPECT_FALSE(unstable_fixed_point(*centre.plan, saddle, c));
  // Where the exact λ₁ is not available (z feeds back), nothing is refused: the saddle of
  // K = p²/2 − q²/2 + c − γz² is kept, described by its orbit as before.
  const Map z = map_of("K = \"p^2/2 - q^2/2 + c - gamma*z^2\"\nc = 0.5\ngamma = 0.2");
  EXPECT_FALSE(unstable_fixed_point(*z.plan, saddle, linearisation_at(*z.plan, 0.0, 0.0)));
}

TEST(UnstableFixedPoint, TheTableRefusesItBeforeLabelling) {
  // The double well's three fixed points, as three blocks' candidates {first lane, value,
  // period, q, p}: the saddle is refused, and the minima are numbered 1, 2 as if it had never
  // been found (3 attractors, numbered 1..3, without the Jacobian).
  const Map well = map_of("K = \"p^2/2 + (q^2 - 1)^2/2 - g*z\"\ng = 0.1");
  const std::vector<double> records{0, 0, 1, -1.0, 0.0, 1, 0, 1, 0.0, 0.0, 2, 0, 1, 1.0, 0.0};
  const AttractorTable before = merge_candidates(*well.plan, records);
  EXPECT_EQ(before.attractors.size(), 3u);
  EXPECT_TRUE(before.refused.empty());
  const AttractorTable after = merge_candidates(*well.plan, records, &fixed_point_linearisation);
  ASSERT_EQ(after.attractors.size(), 2u);
  EXPECT_EQ(after.attractors[0].point, (std::vector<double>{-1.0, 0.0}));
  EXPECT_EQ(after.attractors[1].point, (std::vector<double>{1.0, 0.0}));
  EXPECT_EQ(after.attractors[0].label, 1);
  EXPECT_EQ(after.attractors[1].label, 2);
  // Each kept one holds its linearisation, evaluated once, read by its description.
  ASSERT_TRUE(after.attractors[0].linearisation.has_value());
  EXPECT_NEAR(after.attractors[0].linearisation->lyapunov, -0.05, 1e-15);
  ASSERT_EQ(after.refused.size(), 1u);
  ASSERT_EQ(after.refused[0].size(), 1u);
  EXPECT_EQ(after.refused[0][0].point, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(after.refused[0][0].label, 0);
}

}  // namespace
}  // namespace cs
