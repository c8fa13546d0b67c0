// The double-well basin measure: the energy trap's margin, early stop against integration to
// t_end, and labels against an independent accurate integration.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "numerics/method_list.hpp"
#include "engine/run_plan.hpp"
#include "physics/double_well.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

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
        energy[n] = DoubleWell::energy(x.q[0], x.p[0], a);
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
// ≤ 0.19 for contact_splitting4, ≤ 0.01 for contact_splitting6 and rk4.
template <class Method>
void expect_margin_covers_twice() {
  const double margin_coefficient = RunPlan::basin_margin_coefficient;  // what runs use
  for (double h : {0.01, 0.05, 0.2}) {
    for (double a : {1.0, 1.5}) {
      for (double gamma : {0.0, 0.1}) {
        double rise = largest_energy_rise<Method>(h, a, gamma);
        double margin = margin_coefficient * h * h * std::pow(a, 6);
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
  return DoubleWell::energy(q, p, 1.0) < 0.5 ? (q > 0 ? 1 : -1) : 0;
}

TEST(BasinTrap, LabelsOfChosenStatesMatchAnAccurateReference) {
  const std::vector<std::pair<double, double>> states{
      {0.5, 0.0}, {-0.5, 0.3}, {2.0, 0.0}, {-2.0, 0.0}, {1.5, 1.5}, {-2.5, -1.0}, {0.2, -2.0}};
  std::string q_values, p_values;
  for (auto [q, p] : states) {
    q_values += std::to_string(q) + ",";
    p_values += std::to_string(p) + ",";
  }
  for (std::size_t i = 0; i < states.size(); ++i) {
    auto [q, p] = states[i];
    auto r = test::run_in_memory(R"(
      [scene]
      name = "double_well"
      [measures]
      basin = {})", {"initial.q=" + std::to_string(q), "initial.p=" + std::to_string(p)});
    EXPECT_EQ(r["basin"][0], reference_basin(q, p)) << "q0 " << q << " p0 " << p;
  }
  // (0.5, 0) starts below the saddle energy: decided at once.
  auto inside = test::run_in_memory("[scene]\nname = \"double_well\"\n[measures]\nbasin = {}",
                                    {"initial.q=0.5", "initial.p=0.0"});
  EXPECT_EQ(inside["settle_time"][0], 0.0);
  // The saddle point (0, 0) is an equilibrium: it never settles.
  auto saddle = test::run_in_memory("[scene]\nname = \"double_well\"\n[measures]\nbasin = {}",
                                    {"initial.q=0.0", "initial.p=0.0"});
  EXPECT_EQ(saddle["basin"][0], 0.0);
  EXPECT_TRUE(std::isnan(saddle["settle_time"][0]));
}

}  // namespace
}  // namespace cs
