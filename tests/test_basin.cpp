// The double-well basin measure: the energy trap's margin, early stop against integration to
// t_end, the trap's decision at t = 0 against its theory, and labels against an independent
// accurate integration. The double well has no trap of its own: the general energy trap
// (physics/energy_wells.hpp) serves it, and its label rule gives −1/+1.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "numerics/method_list.hpp"
#include "engine/mappers/energy_trap.hpp"
#include "engine/mappers/energy_trap_record.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"
#include "io/linspace.hpp"
#include "physics/double_well.hpp"
#include "physics/energy_wells.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

// E = p²/2 + U(q); dE/dt = −γp², so it never increases for γ ≥ 0.
double energy(double q, double p, double a) {
  const double well = q * q - a * a;
  return 0.5 * (p * p) + 0.5 * (well * well);
}

// The trap level the general energy trap finds for the double well over a map of |q| ≤ 3a.
double trap_level(double h, double a, double gamma) {
  BasinBox<1> box;
  box.lo[0] = -4.5 * a, box.hi[0] = 4.5 * a;
  return find_wells<DoubleWell>({a, gamma}, box, h).trap_energy;
}

// Largest rise of E = p²/2 + U(q) after any step at which E < a⁴/2, over a grid of
// initial states: the amount the trap's margin must cover.
template <class Method>
double largest_energy_rise(double h, double a, double gamma) {
  ParamsOf<DoubleWell, double> c{a, gamma};
  const long steps = std::lround(20.0 / h);
  double worst = 0.0;
  std::vector<double> energy(static_cast<std::size_t>(steps + 1));
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      LaneState<1> x{};
      x.q[0] = a * (-2.0 + 4.0 * i / 39);
      x.p[0] = a * a * (-2.0 + 4.0 * j / 39);
      Method::template start<DoubleWell>(x, c);
      auto k = Method::template coefficients<DoubleWell>(h, c, x);
      for (long n = 0; n <= steps; ++n) {
        energy[n] = cs::energy(x.q[0], x.p[0], a);
        Method::template step<DoubleWell, Carry{false, false}>(x, c, k);
      }
      double later_max = -INFINITY;
      for (long n = steps; n >= 0; --n) {
        if (energy[n] < 0.5 * a * a * a * a) worst = std::max(worst, later_max - energy[n]);
        later_max = std::max(later_max, energy[n]);
      }
    }
  }
  return worst;
}

// γ = 0 is the worst case: no damping to outweigh the integrator's energy oscillation.
// Measured (in units of h²a⁶, h = 0.01 … 0.2, a = 1 and 1.5): 0.75 … 0.92 for the second-order
// methods (at γ = 0 the hybrid and symmetric leap-frogs and Strang splitting coincide),
// ≤ 0.19 for contact_splitting4, ≤ 0.01 for contact_splitting6 and rk4. The general trap's
// margin h²·κ·ΔE is 2h²a⁶ here (κ = U''(±a) = 4a², ΔE = a⁴/2): checked, then held against
// the rise (at γ = 0 the trap is not used, but the margin is what it would be).
template <class Method>
void expect_margin_covers_twice() {
  for (double h : {0.01, 0.05, 0.2}) {
    for (double a : {1.0, 1.5}) {
      const double margin = 0.5 * std::pow(a, 4) - trap_level(h, a, 0.1);
      EXPECT_NEAR(margin, 2.0 * h * h * std::pow(a, 6), 1e-6 * h * h * std::pow(a, 6))
          << "h " << h << " a " << a;
      for (double gamma : {0.0, 0.1}) {
        double rise = largest_energy_rise<Method>(h, a, gamma);
        EXPECT_LT(rise, 0.5 * margin) << "h " << h << " a " << a << " gamma " << gamma;
      }
    }
  }
}

TEST(BasinTrap, MarginCoversTheEnergyRiseOfEveryMethodTwice) {
  Methods::for_each([]<class Method>() { expect_margin_covers_twice<Method>(); });
}

const char* kMap = R"(
  [scene]
  name = "double_well"
  [integrator]
  t_end = 100.0
  [grid]
  q_0 = { from = -3.0, to = 3.0, n = 96 }
  p_0 = { from = -3.0, to = 3.0, n = 96 }
  [measures]
  basin = {}
  final_state = { vars = ["q"] })";

TEST(BasinTrap, EarlyStopLabelsEqualLabelsAtTheEndOnAWholeMap) {
  auto early = test::run_in_memory(kMap);
  auto full = test::run_in_memory(kMap, {"measures.basin.early_stop=false"});
  const auto& a = early["basin"];
  const auto& b = full["basin"];
  ASSERT_EQ(a.size(), b.size());
  std::size_t decided = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i], b[i]) << "cell " << i;
    ASSERT_EQ(std::isnan(early["settle_time"][i]), std::isnan(full["settle_time"][i]));
    if (a[i] != 0) {
      ++decided;
      ASSERT_EQ(early["settle_time"][i], full["settle_time"][i]) << "cell " << i;
      // Integrated to the end, the lane sits in the well of its label.
      ASSERT_GT(b[i] * full["final_q"][i], 0.0) << "cell " << i;
    }
  }
  // Nearly every cell settles well before t = 100 at γ = 0.1; a test where none did would
  // compare nothing.
  EXPECT_GT(static_cast<double>(decided) / a.size(), 0.99);
}

// The trap with per-lane parameters (a grid axis over a, the last axis: a alternates from lane
// to lane) decides each lane as a run of that lane's parameters alone does (one parameter set:
// the uniform path): the trap looks at a lane only when the screen flags it (no looks on a
// schedule), inside that lane's own wells' box and below its own level. Wells at ±0.6 and
// ±1.6 have boxes and levels of their own. The same bits, cell for cell, in settle_time,
// status and the final state, and the same cells decided: a lane's result depends on its own
// start and parameters alone. t_end = 10: only the trap settles lanes this early.
TEST(BasinTrap, PerLaneParametersDecideAsEachParameterSetAlone) {
  const std::string map = R"(
  [scene]
  name = "double_well"
  [integrator]
  t_end = 10.0
  [grid]
  q_0 = { from = -2.5, to = 2.5, n = 24 }
  p_0 = { from = -1.0, to = 1.0, n = 8 }
  a = { values = [1.6, 0.6] }
  [measures]
  basin = {}
  final_state = { vars = ["q", "p"] }
  )";
  const double a[] = {1.6, 0.6};
  auto both = test::run_in_memory(map);
  const std::size_t cells = 24 * 8;
  int decided[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    auto alone = test::run_in_memory(map, {k == 0 ? "grid.a={values=[1.6]}" : "grid.a={values=[0.6]}"});
    // The labels are numbered over each run's own table (four attractors here, two alone):
    // compared as decided or not; where and when a lane settled, bit for bit.
    for (const char* name : {"basin", "settle_time", "status", "final_q", "final_p"}) {
      ASSERT_EQ(alone[name].size(), cells) << name;
      const bool label = std::string(name) == "basin";
      for (std::size_t i = 0; i < cells; ++i) {
        double x = both[name][2 * i + k], y = alone[name][i];
        if (label) x = x != 0.0, y = y != 0.0;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(x), std::bit_cast<std::uint64_t>(y))
            << name << ", a = " << a[k] << ", cell " << i << ": " << x << " vs " << y;
      }
    }
    for (std::size_t i = 0; i < cells; ++i)
      decided[k] += alone["basin"][i] != 0 && alone["settle_time"][i] > 0.0;
  }
  // Lanes the trap settled after t = 0 (on a screen's flag) at each a (48 and 20); a map where
  // none did would compare nothing the flag decides.
  EXPECT_GT(decided[0], 10);
  EXPECT_GT(decided[1], 10);
}

// The trap's decision at t = 0, cell by cell: a state whose E is below the level
// a⁴/2 − 2h²a⁶ is decided at once (settle_time 0) for the well it is in (the sign of q0: the
// label rule), and one whose E is at or above the saddle's a⁴/2 is not.
TEST(BasinTrap, DecisionsAtTheStartFollowTheTrapLevel) {
  auto r = test::run_in_memory(kMap);
  const double h = 0.01, level = 0.5 - 2.0 * h * h;
  const auto axis = linspace(-3.0, 3.0, 96);
  int at_once = 0;
  for (std::size_t i = 0; i < 96; ++i)
    for (std::size_t j = 0; j < 96; ++j) {
      const double q0 = axis[i], p0 = axis[j];
      const std::size_t cell = i * 96 + j;
      const double e0 = energy(q0, p0, 1.0);
      if (e0 < level - 1e-12) {
        ++at_once;
        EXPECT_EQ(r["settle_time"][cell], 0.0) << "q0 " << q0 << " p0 " << p0;
        EXPECT_EQ(r["basin"][cell], q0 > 0.0 ? 1.0 : -1.0) << "q0 " << q0 << " p0 " << p0;
      } else if (e0 >= 0.5) {
        EXPECT_FALSE(r["settle_time"][cell] == 0.0) << "q0 " << q0 << " p0 " << p0;
      }
    }
  EXPECT_GT(at_once, 500);  // a test where no state starts trapped would compare nothing
}

// Independent reference: classical RK4 on q' = p, p' = −U'(q) − γp at h = 1e-3.
int reference_basin(double q, double p, double gamma = 0.1) {
  auto force = [&](double q, double p) { return -2.0 * q * (q * q - 1.0) - gamma * p; };
  const double h = 1e-3;
  for (int n = 0; n < 100000; ++n) {
    double k1q = p, k1p = force(q, p);
    double k2q = p + 0.5 * h * k1p, k2p = force(q + 0.5 * h * k1q, p + 0.5 * h * k1p);
    double k3q = p + 0.5 * h * k2p, k3p = force(q + 0.5 * h * k2q, p + 0.5 * h * k2p);
    double k4q = p + h * k3p, k4p = force(q + h * k3q, p + h * k3p);
    q += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    p += h / 6 * (k1p + 2 * k2p + 2 * k3p + k4p);
  }
  return energy(q, p, 1.0) < 0.5 ? (q > 0 ? 1 : -1) : 0;
}

// Chosen states as one map (the trap's box, from the map's positions, then holds both wells and
// the saddle: a single state's box, q0 ± 1/2, would hold at most one well).
TEST(BasinTrap, LabelsOfChosenStatesMatchAnAccurateReference) {
  const std::vector<double> qs{0.5, -0.5, 2.0, -2.0, 1.5, -2.5, 0.2, 0.0};
  const std::vector<double> ps{0.0, 0.3, 1.5, -1.0, -2.0};
  auto list = [](const std::vector<double>& v) {
    std::string text;
    for (double x : v) text += (text.empty() ? "" : ", ") + std::to_string(x);
    return "{ values = [" + text + "] }";
  };
  auto r = test::run_in_memory(R"(
    [scene]
    name = "double_well"
    [measures]
    basin = {})", {"grid.q_0=" + list(qs), "grid.p_0=" + list(ps)});
  for (std::size_t i = 0; i < qs.size(); ++i)
    for (std::size_t j = 0; j < ps.size(); ++j)
      EXPECT_EQ(r["basin"][i * ps.size() + j], reference_basin(qs[i], ps[j]))
          << "q0 " << qs[i] << " p0 " << ps[j];
  // (0.5, 0) starts below the saddle energy: decided at once.
  EXPECT_EQ(r["settle_time"][0 * ps.size() + 0], 0.0);
  // The saddle point (0, 0) is an equilibrium: it never settles (the energy trap refuses it as
  // an attractor, which the anchor test alone would take it for).
  EXPECT_EQ(r["basin"][7 * ps.size() + 0], 0.0);
  EXPECT_TRUE(std::isnan(r["settle_time"][7 * ps.size() + 0]));
}

// A 1-D K with four wells of different depths (minima near ±1, ±2; maxima near 0, ±1.5):
// V = (q² − 1)²(q² − 4)²/8 + q/20.
struct FourWells {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = false;
  static constexpr bool kz_constant = true;
  static constexpr bool kz_state_free = true;
  static constexpr bool time_dependent = false;
  static constexpr bool p_in_forces = false;
  static constexpr ZPart z_part = ZPart::linear;
  template <class T>
  struct Params {
    T gamma;
  };
  template <class T>
  static Params<T> params_from(const T* v) { return {v[0]}; }
  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    const auto qq = square(q<0>(x));
    return half_square(p<0>(x)) + (square(qq - 1.0) * square(qq - 4.0)) * 0.125 +
           q<0>(x) * 0.05 - c.gamma * z(x);
  }
  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }
};

// One q: the well read off the critical points (WellFinder::bottom) is the steepest descent's,
// for random trapped states (E = p²/2 + V(q) below the level, inside the box), and every well
// below the level gets some of them.
template <class S>
void expect_lookup_equals_descent(const ParamsOf<S, double>& c, const BasinBox<1>& box,
                                  std::size_t wells_expected) {
  const Wells<1> wells = find_wells<S>(c, box, 0.01);
  ASSERT_EQ(wells.verdict, TrapVerdict::used);
  ASSERT_EQ(wells.minima.size(), wells_expected);
  const WellFinder<S> finder(c, wells.box, 0.01);
  std::mt19937_64 random(26);
  std::uniform_real_distribution<double> uq(wells.box.lo[0], wells.box.hi[0]), up(-1.5, 1.5);
  std::vector<int> hits(wells.minima.size(), 0);
  int trapped = 0;
  for (int k = 0; k < 200000 && trapped < 5000; ++k) {
    const double q = uq(random), p = up(random);
    if (!(0.5 * p * p + potential<S>(&q, c, 0.0) < wells.trap_energy)) continue;
    ++trapped;
    const std::array<double, 1>* looked_up = WellFinder<S>::bottom_on_line(q, wells);
    std::array<double, 1> descended{}, bottom{};
    ASSERT_NE(looked_up, nullptr) << "q " << q;
    ASSERT_TRUE(finder.descend(&q, wells, descended)) << "q " << q;
    ASSERT_EQ((*looked_up)[0], descended[0]) << "q " << q;
    ASSERT_TRUE(finder.bottom(&q, wells, bottom)) << "q " << q;
    ASSERT_EQ(bottom[0], (*looked_up)[0]) << "q " << q;
    for (std::size_t m = 0; m < wells.minima.size(); ++m) hits[m] += wells.minima[m] == *looked_up;
  }
  EXPECT_EQ(trapped, 5000);
  for (std::size_t m = 0; m < wells.minima.size(); ++m)
    EXPECT_GT(hits[m], 100) << "minimum at " << wells.minima[m][0];
}

TEST(BasinTrap, OneDimensionalLookupEqualsTheDescentOfTheDoubleWell) {
  BasinBox<1> box;
  box.lo[0] = -6.0, box.hi[0] = 6.0;  // the paper's map, q0 ∈ [−3, 3]
  expect_lookup_equals_descent<DoubleWell>({1.0, 0.1}, box, 2);
}

TEST(BasinTrap, OneDimensionalLookupEqualsTheDescentOfFourWells) {
  BasinBox<1> box;
  box.lo[0] = -3.5, box.hi[0] = 3.5;
  expect_lookup_equals_descent<FourWells>({0.1}, box, 4);
}

// A box whose boundary is below the lanes' largest initial energy grows (around the positions,
// by doublings of the widening) until it is above it: one point q0 = 2 of the double well
// (E0 = V(2) = 9/2; V > 9/2 only where |q| > 2) gets [2 − 8, 2 + 8], the first whose lower end
// is below −2. One whose boundary is above E0 (the paper's map) stays as it is; an E0 no box
// confines leaves the first box.
TEST(BasinTrap, TheBoxGrowsUntilVOnItsBoundaryIsAboveTheInitialEnergy) {
  const ParamsOf<DoubleWell, double> c{1.0, 0.1};
  BasinBox<1> point;
  point.lo[0] = point.hi[0] = 2.0;
  const std::array<double, 1> half{0.5};
  BasinBox<1> box = confining_box<DoubleWell>(c, point, half, 4.5, 0.01);
  EXPECT_EQ(box.lo[0], -6.0);
  EXPECT_EQ(box.hi[0], 10.0);
  const Wells<1> wells = find_wells<DoubleWell>(c, box, 0.01);
  EXPECT_EQ(wells.verdict, TrapVerdict::used);
  EXPECT_EQ(wells.minima.size(), 2u);
  EXPECT_NEAR(wells.trap_energy, 0.5 - 2e-4, 1e-9);  // a⁴/2 − 2h²a⁶, the old trap's level
  EXPECT_GT(wells.confinement, 4.5);
  // Unchanged: no growth needed, or none that helps.
  BasinBox<1> map;
  map.lo[0] = -3.0, map.hi[0] = 3.0;
  box = confining_box<DoubleWell>(c, map, {3.0}, 36.5, 0.01);
  EXPECT_EQ(box.lo[0], -6.0);
  EXPECT_EQ(box.hi[0], 6.0);
  box = confining_box<DoubleWell>(c, point, half, 1e12, 0.01);
  EXPECT_EQ(box.lo[0], 1.5);
  EXPECT_EQ(box.hi[0], 2.5);
  // Without growth the point's own box knows the well at +1 alone (Newton reaches q = 1 from
  // inside [1.5, 2.5]), not the one at −1 where the lane (2, 0) ends: it would never be trapped.
  const Wells<1> own = find_wells<DoubleWell>(c, box, 0.01);
  ASSERT_EQ(own.minima.size(), 1u);
  EXPECT_NEAR(own.minima[0][0], 1.0, 1e-12);
}

// The energy trap's wells are kept once per process and shared by the runs whose wells are the
// same: they are keyed on what the box depends on, among it the kinetic part of the largest
// initial energy E0 (each p's largest p²/2), not on the grid's p values themselves. One q0 = 2
// with p0 up to 0.1 (E0 = 4.505: the box [−6, 10], as above) or up to 40 (E0 = 804.5: the box
// [−14, 18]) gives another box, and so another confinement (E below it never reaches the box's
// boundary: V's least value there less 1 % of its range), which decides_alone reads; p0 in
// {40, 0, −40} has the same E0 as ±40 and shares its wells. Each trap must see its own grid's
// confinement, in whichever order the runs come.
// The trap's level depends on the step (a⁴/2 − 2h²a⁶ for the double well), so the wells kept
// per process are keyed on h too: two runs of one grid and parameters at h = 0.01 and 0.1 (an
// h axis's slices) each trap at their own level. A lane with E = 0.49 lies between them
// (0.4998 and 0.48): trapped at h = 0.01, not at h = 0.1.
TEST(BasinTrap, EachStepHasItsOwnLevel) {
  const ParamsOf<DoubleWell, double> c{1.0, 0.421875};  // no other test's: fresh wells
  const RunSpec spec = parse_run_spec(
      "[scene]\nname = \"double_well\"\na = 1.0\ngamma = 0.421875\n[integrator]\nh = 0.01\n"
      "t_end = 10.0\n[grid]\nq_0 = { from = -2.0, to = 2.0, n = 9 }\n[measures]\nbasin = {}\n",
      {}, "test spec");
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  for (const double h : {0.01, 0.1}) {
    SCOPED_TRACE(h);
    EnergyTrap<DoubleWell, true, 64> trap(plan, true, LaneClock{0.0, h}, c);
    LaneState<1> x{};
    x.q[0] = 0.5;  // V = 0.28125
    x.p[0] = std::sqrt(2.0 * (0.49 - 0.28125));
    Settlement<2> s;
    trap.look(0, 0, x, c, s);
    EXPECT_EQ(s.settled, h == 0.01);
    if (s.settled) {
      EXPECT_NEAR(s.point[0], 1.0, 1e-12);
    }
  }
}

// The memory check counts what the trap's record of the wells keeps for the process's
// lifetime (energy_trap_record_bytes): a copy of each q's values over the grid, where their
// combinations are few enough for E₀ to visit (at most 2^22), else none; nothing without the
// trap or without a basin map.
TEST(BasinTrap, RecordBytesAreTheQValuesItKeeps) {
  const auto bytes = [](const std::string& scene, const std::string& grid, const std::string& basin) {
    const RunSpec spec = parse_run_spec("[scene]\nname = \"" + scene + "\"\n[integrator]\nh = 0.01\n"
                                        "t_end = 1.0\n[grid]\n" + grid + "[measures]\n" + basin + "\n",
                                        {}, "test spec");
    return energy_trap_record_bytes(RunPlan(spec, *find_scene(spec.scene), *find_method(spec.method)));
  };
  const std::string line = "q_0 = { from = -2.0, to = 2.0, n = 1000 }\n";
  EXPECT_EQ(bytes("double_well", line, "basin = {}"), 1000.0 * sizeof(double));
  EXPECT_EQ(bytes("double_well", line + "p_0 = { from = -1.0, to = 1.0, n = 7 }\n", "basin = {}"),
            1000.0 * sizeof(double));  // p's values are not kept
  EXPECT_EQ(bytes("double_well", "p_0 = { from = -1.0, to = 1.0, n = 7 }\n", "basin = {}"),
            1.0 * sizeof(double));  // q fixed: its one value
  EXPECT_EQ(bytes("double_well", line, "basin = { exact_trap = false }"), 0.0);
  EXPECT_EQ(bytes("double_well", line, "final_state = true"), 0.0);
  EXPECT_EQ(bytes("coupled_oscillators", "q1_0 = { from = -1.0, to = 1.0, n = 2048 }\n"
                                         "q2_0 = { from = -1.0, to = 1.0, n = 2048 }\n", "basin = {}"),
            4096.0 * sizeof(double));  // 2^22 combinations: visited
  EXPECT_EQ(bytes("coupled_oscillators", "q1_0 = { from = -1.0, to = 1.0, n = 2048 }\n"
                                         "q2_0 = { from = -1.0, to = 1.0, n = 2049 }\n", "basin = {}"),
            0.0);  // one more: E₀ is +∞, nothing kept
}

TEST(BasinTrap, RunsShareTheWellsOnlyWhereTheirInitialEnergiesAgree) {
  const double gamma = 0.4375;  // no other test's: the process-wide wells start empty for it
  const ParamsOf<DoubleWell, double> c{1.0, gamma};
  const auto confinement = [&](double p_max) {
    BasinBox<1> point;
    point.lo[0] = point.hi[0] = 2.0;
    const double e0 = 0.5 * p_max * p_max + 4.5;  // V(2) = (4 − 1)²/2
    return find_wells<DoubleWell>(c, confining_box<DoubleWell>(c, point, {0.5}, e0, 0.01), 0.01).confinement;
  };
  // V at the box's ends is exact in doubles (V(−6) = 612.5, V(10) = 4900.5, V(−14) = 19012.5,
  // V(18) = 52164.5); the level less 1 % of the range rounds a few times: 1e-9 is ~1e5 ulps.
  ASSERT_NEAR(confinement(0.1), 612.5 - 0.01 * (4900.5 - 612.5), 1e-9);
  ASSERT_NEAR(confinement(40.0), 19012.5 - 0.01 * (52164.5 - 19012.5), 1e-9);
  for (const char* p_axis : {"[-0.1, 0.1]", "[-40.0, 40.0]", "[40.0, 0.0, -40.0]", "[0.1, -0.1]"}) {
    SCOPED_TRACE(p_axis);
    const std::string text = "[scene]\nname = \"double_well\"\na = 1.0\ngamma = 0.4375\n[initial]\nq = 2.0\n"
                             "[integrator]\nh = 0.01\nt_end = 10.0\n[grid]\np_0 = { values = " +
                             std::string(p_axis) + " }\n[measures]\nbasin = {}\n";
    const RunSpec spec = parse_run_spec(text, {}, "test spec");
    const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
    const EnergyTrap<DoubleWell, true, 64> trap(plan, true, LaneClock{0.0, 0.01}, c);
    ASSERT_TRUE(trap.active());
    const double level = confinement(std::string(p_axis).find("40") != std::string::npos ? 40.0 : 0.1);
    for (double e : {level * (1.0 - 1e-9), level * (1.0 + 1e-9)}) {
      LaneState<1> x{};
      x.q[0] = 0.0;  // V(0) = 0.5: E = 0.5 + p²/2
      x.p[0] = std::sqrt(2.0 * (e - 0.5));
      EXPECT_EQ(trap.decides_alone(x, c), e < level) << "E " << e << ", confinement " << level;
    }
  }
}

// Maps whose positions do not span the wells: one point (q0, p0) = (2, 0), and q0 ∈ [1.5, 2.5].
// The trap serves them (every lane's verdict "used") and decides each lane as it does in a map
// that spans both wells (the same label, the accurate reference's; the same settle time, bit
// for bit), as the old double-well trap (E < a⁴/2 − 2h²a⁶ at any grid size) did. (2, 0) swings
// over the saddle once and ends in the well at −1.
TEST(BasinTrap, MapsThatDoNotSpanTheWellsSettleThroughTheTrap) {
  const char* spec = R"(
    [scene]
    name = "double_well"
    [integrator]
    t_end = 100.0
    [measures]
    basin = {})";
  auto verdicts_used = [](const test::Datasets& r) {
    const auto& v = r.at("trap_verdict");
    double used = 0.0, all = 0.0;
    for (std::size_t k = 0; k < v.size(); ++k) {
      all += v[k];
      if (k % kTrapVerdicts == static_cast<std::size_t>(TrapVerdict::used)) used += v[k];
    }
    return used == all ? used : -1.0;
  };
  const auto wide = test::run_in_memory(
      spec, {"grid.q_0={ values = [-3.0, -1.0, 0.5, 1.5, 1.75, 2.0, 2.25, 2.5] }", "grid.p_0={ values = [0.0] }"});
  const auto one = test::run_in_memory(spec, {"grid.p_0={ values = [0.0] }"});
  ASSERT_EQ(one.at("basin").size(), 1u);
  EXPECT_EQ(verdicts_used(one), 1.0);
  EXPECT_EQ(one.at("basin")[0], -1.0);
  EXPECT_EQ(one.at("basin")[0], reference_basin(2.0, 0.0));
  EXPECT_EQ(one.at("basin")[0], wide.at("basin")[5]);
  EXPECT_EQ(one.at("settle_time")[0], wide.at("settle_time")[5]);
  EXPECT_LT(one.at("settle_time")[0], 100.0);
  const auto narrow = test::run_in_memory(
      spec, {"grid.q_0={ from = 1.5, to = 2.5, n = 5 }", "grid.p_0={ values = [0.0] }"});
  EXPECT_EQ(verdicts_used(narrow), 5.0);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(narrow.at("basin")[i], wide.at("basin")[3 + i]) << "q0 " << 1.5 + 0.25 * i;
    EXPECT_EQ(narrow.at("basin")[i], reference_basin(1.5 + 0.25 * i, 0.0)) << "q0 " << 1.5 + 0.25 * i;
    EXPECT_EQ(narrow.at("settle_time")[i], wide.at("settle_time")[3 + i]) << "q0 " << 1.5 + 0.25 * i;
  }
}

}  // namespace
}  // namespace cs
