// Accuracy of every integrator, each property written once for all methods (odeint's
// test/numeric/symplectic.cpp does the same): the observed order against the exact flow of
// scene A, the long-time behaviour of H = λK, agreement of all methods on all four scenes as h
// shrinks, and the run path (spec → dispatch → tiled kernel) equal to direct steps. The pieces
// the splitting methods and the symmetric leap-frog rest on: test_splitting_parts.cpp.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kernel_build/kernel_source.hpp"
#include "numerics/method_catalog.hpp"
#include "numerics/method_list.hpp"
#include "physics/coupled_oscillators.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/double_well.hpp"
#include "physics/z2_damping.hpp"
#include "support/all_methods.hpp"
#include "support/exact_damped_oscillator.hpp"
#include "support/format_number.hpp"
#include "support/linear_step_map.hpp"
#include "support/time_dependent_scenes.hpp"
#include "support/run_in_memory.hpp"

namespace cs {
namespace {

constexpr Carry kAll{true, true};

// How H = λK behaves over long times on scene A.
enum class LongTimeH { bounded, drifts, tested_elsewhere };

// What the tests expect of a method beyond its catalog entry (which gives the order).
// exact_log_lambda: where K_z is constant, (ln λ)' = −K_z is integrated exactly (RK4 is exact
// on a constant rate; a splitting touches λ only in the exact Z flow).
template <class M>
struct Traits;
template <>
struct Traits<HybridLeapfrog> {
  static constexpr LongTimeH long_time_h = LongTimeH::tested_elsewhere;  // test_hybrid_leapfrog
  static constexpr bool exact_log_lambda = false;
};
template <>
struct Traits<SymmetricLeapfrog> {
  static constexpr LongTimeH long_time_h = LongTimeH::bounded;
  static constexpr bool exact_log_lambda = false;
};
template <>
struct Traits<ContactSplitting2> {
  static constexpr LongTimeH long_time_h = LongTimeH::bounded;
  static constexpr bool exact_log_lambda = true;
};
template <>
struct Traits<ContactSplitting4> {
  static constexpr LongTimeH long_time_h = LongTimeH::bounded;
  static constexpr bool exact_log_lambda = true;
};
template <>
struct Traits<ContactSplitting6> {
  static constexpr LongTimeH long_time_h = LongTimeH::bounded;
  static constexpr bool exact_log_lambda = true;
};
template <>
struct Traits<Rk4> {
  static constexpr LongTimeH long_time_h = LongTimeH::drifts;
  static constexpr bool exact_log_lambda = true;
};

template <class M>
int catalog_order() {
  const MethodInfo* info = find_method(M::description.name);
  if (info == nullptr) ADD_FAILURE() << M::description.name << " is not in the method catalog";
  return info ? info->order : 0;
}

template <class M>
class EveryMethod : public ::testing::Test {};
using test::AllMethods;
struct MethodNames {
  template <class M>
  static std::string GetName(int) {
    return std::string(M::description.name);
  }
};
TYPED_TEST_SUITE(EveryMethod, AllMethods, MethodNames);

// The catalog is built from the generated list: every method once, in the order of their
// catalog_position (the order `contactsweep methods` and the spec's errors list them).
TEST(MethodCatalog, ListsEveryMethodOnceInCatalogOrder) {
  const std::vector<std::string> expected{"hybrid_leapfrog",    "symmetric_leapfrog",
                                          "contact_splitting2", "contact_splitting4",
                                          "contact_splitting6", "rk4",
                                          "dop853"};
  std::vector<std::string> listed;
  for (const MethodInfo& m : method_catalog()) listed.push_back(m.name);
  EXPECT_EQ(listed, expected);
  Methods::for_each([]<class M>() {
    const MethodInfo* info = find_method(M::description.name);
    ASSERT_NE(info, nullptr) << M::description.name;
    EXPECT_EQ(info->order, M::description.order);
    EXPECT_EQ(info->force_evaluations_per_step, M::description.force_evaluations_per_step);
    EXPECT_EQ(info->needs_split_parts.size(), M::description.needs_split_parts.size());
  });
}

// A kernel compiled at run time names the method's type and header as the generated list
// spells them (numerics/method_list.hpp): the header must be the method's own file.
TEST(MethodCatalog, KernelSourceIncludesTheMethodsOwnFile) {
  Methods::for_each([]<class M>() {
    const std::string name(M::description.name);
    const std::string source = kernel_source("", "Scene", {name, Carry{false, false}, true});
    EXPECT_NE(source.find("#include \"numerics/methods/" + name + ".hpp\""), std::string::npos)
        << source;
    EXPECT_NE(source.find("cs::" + std::string(MethodSourceOf<M>::value.type) + ","),
              std::string::npos)
        << source;
  });
}

// ---- the scenes with the paper's parameters and initial states --------------------------------

template <class S>
struct PaperScene;
template <>
struct PaperScene<DampedOscillator> {
  static ParamsOf<DampedOscillator, double> params() { return {1.0, 0.1}; }
  static constexpr double q[1] = {1.0};
  static constexpr double h_scale = 1.0;
};
template <>
struct PaperScene<Z2Damping> {
  static ParamsOf<Z2Damping, double> params() { return {1.0, 0.1}; }
  static constexpr double q[1] = {1.0};
  static constexpr double h_scale = 1.0;
};
template <>
struct PaperScene<DoubleWell> {
  static ParamsOf<DoubleWell, double> params() { return {1.0, 0.1}; }
  static constexpr double q[1] = {2.0};
  // From q = 2 the well's curvature U'' = 6q² − 2 is 22: a 4.7× faster oscillation than A's.
  static constexpr double h_scale = 0.25;
};
template <>
struct PaperScene<CoupledOscillators> {
  static ParamsOf<CoupledOscillators, double> params() { return {1.2, 0.8, 0.8, 0.01}; }
  static constexpr double q[2] = {1.0, -1.0};
  static constexpr double h_scale = 0.5;
};

// p = 0, z = λ = 1, as in the paper; started for method M.
template <class M, class S>
LaneState<S::dof> paper_start(const ParamsOf<S, double>& c) {
  LaneState<S::dof> x{};
  for (int d = 0; d < S::dof; ++d) x.q[d] = PaperScene<S>::q[d];
  x.z = 1.0;
  x.mu = 0.0;
  M::template start<S>(x, c);
  return x;
}

// The state at t = 1, 2, ..., 10 (a single end time could sit near a zero of the error).
template <class M, class S>
std::vector<LaneState<S::dof>> states_at_whole_times(double h) {
  const auto c = PaperScene<S>::params();
  auto x = paper_start<M, S>(c);
  const auto k = M::template coefficients<S>(h, c, x);
  const auto per_unit = std::llround(1.0 / h);
  std::vector<LaneState<S::dof>> out;
  for (int t = 1; t <= 10; ++t) {
    for (long n = 0; n < per_unit; ++n) M::template step<S, kAll>(x, c, k);
    out.push_back(x);
  }
  return out;
}

// ln λ of a lane from a short run (no fold of its λ products yet), whatever its scene.
template <int D>
double unfolded_log_lambda(const LaneState<D>& x) {
  return x.mu + (std::log(x.lambda_numerator) - std::log(x.lambda_denominator));
}

template <int D>
double max_distance(const std::vector<LaneState<D>>& a, const std::vector<LaneState<D>>& b) {
  double e = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int d = 0; d < D; ++d)
      e = std::max({e, std::fabs(a[i].q[d] - b[i].q[d]), std::fabs(a[i].p[d] - b[i].p[d])});
    e = std::max({e, std::fabs(a[i].z - b[i].z), std::fabs(unfolded_log_lambda(a[i]) - unfolded_log_lambda(b[i]))});
  }
  return e;
}

// ---- order against the exact flow of scene A --------------------------------------------------

struct Errors {
  double q, p, z, log_lambda;
};

template <class M>
Errors scene_a_errors(double h) {
  using S = DampedOscillator;
  const auto states = states_at_whole_times<M, S>(h);
  Errors e{0, 0, 0, 0};
  for (int t = 1; t <= 10; ++t) {
    const auto& x = states[t - 1];
    auto ex = test::exact_damped_oscillator(t, 1.0, 0.1, 1.0, 0.0, 1.0, 1.0);
    e.q = std::max(e.q, std::fabs(x.q[0] - ex.q));
    e.p = std::max(e.p, std::fabs(x.p[0] - ex.p));
    e.z = std::max(e.z, std::fabs(x.z - ex.z));
    e.log_lambda = std::max(e.log_lambda, std::fabs(log_lambda<S>(x) - ex.log_lambda));
  }
  return e;
}

TYPED_TEST(EveryMethod, ObservedOrderOnTheExactSceneA) {
  using M = TypeParam;
  const int order = catalog_order<M>();
  // Four halvings of h in the asymptotic range, with the smallest error (≳ 1e-9, measured)
  // far above round-off (≲ 1e-13 over ≤ 800 steps). Order 6 needs h ~ 0.5 for that.
  const double h0 = order == 6 ? 0.5 : 0.1;
  std::vector<double> hs{h0, h0 / 2, h0 / 4, h0 / 8};
  std::vector<Errors> errors;
  for (double h : hs) errors.push_back(scene_a_errors<M>(h));
  for (std::size_t i = 0; i + 1 < hs.size(); ++i) {
    SCOPED_TRACE("h = " + std::to_string(hs[i]));
    auto observed = [&](double Errors::*m) { return std::log2(errors[i].*m / errors[i + 1].*m); };
    // Second-order methods sit at 2.00 already at h = 0.1 (the paper's method is promised
    // 2.00 ± 0.1); the higher orders approach theirs from above or below by up to 0.05.
    const double tolerance = order == 2 ? 0.1 : 0.2;
    EXPECT_NEAR(observed(&Errors::q), order, tolerance);
    EXPECT_NEAR(observed(&Errors::p), order, tolerance);
    EXPECT_NEAR(observed(&Errors::z), order, tolerance);
    if (!Traits<M>::exact_log_lambda) {
      EXPECT_NEAR(observed(&Errors::log_lambda), order, tolerance);
    }
  }
  if (Traits<M>::exact_log_lambda) {
    // Only round-off: each of the 10/h additions to |ln λ| ≤ 1 rounds by ≤ 2⁻⁵³; margin 2.
    for (std::size_t i = 0; i < hs.size(); ++i)
      EXPECT_LE(errors[i].log_lambda, 10.0 / hs[i] * 0x1p-52) << "h = " << hs[i];
  }
}

// ---- long-time H = λK on scene A ---------------------------------------------------------------

// The bound for a geometric method, derived. At γ = 0 the method's (q, p) map M = [[a, b], [c, d]]
// is symplectic and conserves exactly the quadratic form Q = b p² + (a − d) qp − c q², an
// O(h^order) perturbation of E = (p² + ω²q²)/2: the modified Hamiltonian. Along an orbit E/Q
// therefore ranges over the generalized eigenvalues [μ_min, μ_max] of (E, Q), so E/E₀ − 1
// ranges over [μ_min/μ₀ − 1, μ_max/μ₀ − 1] with μ₀ = E₀/Q₀. With damping, the method conserves
// a modified H̃ = λK̃ whose difference from H is λ(E − Ẽ), and λE stays ≈ E₀: so
//   max |ΔH/H₀| = (E₀/H₀) · max |μ/μ₀ − 1|,
// up to corrections of relative order γ/ω (1 % here) that the γ = 0 form does not see.
template <class M>
double predicted_h_amplitude(double h, double omega, double q0, double p0, double H0) {
  const Eigen::Matrix2d m = test::one_step_matrix<M>(h, omega, 0.0);
  const double a = m(0, 0), b = m(0, 1), c = m(1, 0), d = m(1, 1);
  Eigen::Matrix2d Q;
  Q << -c, 0.5 * (a - d), 0.5 * (a - d), b;
  if (Q(0, 0) < 0.0) Q = -Q;
  EXPECT_LT((m.transpose() * Q * m - Q).norm(), 1e-14) << "Q is not the map's invariant";
  Eigen::Matrix2d E;
  E << 0.5 * omega * omega, 0.0, 0.0, 0.5;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> ratios(E, Q);
  const Eigen::Vector2d x0(q0, p0);
  const double E0 = x0.dot(E * x0), mu0 = E0 / x0.dot(Q * x0);
  const double spread = std::max(std::fabs(ratios.eigenvalues()(0) / mu0 - 1.0),
                                 std::fabs(ratios.eigenvalues()(1) / mu0 - 1.0));
  return E0 / H0 * spread;
}

// γ = 0.01 to t = 10⁴ keeps γt = 100, far from underflow (PHYSICS.md). h is chosen per order so
// that the predicted oscillation (2.6e-5, 4.9e-7, 2.6e-7) stands far above the round-off drift
// of 10⁶ steps (≲ 3e-9, measured with order 4 at h = 0.01).
TYPED_TEST(EveryMethod, LongTimeHOnSceneA) {
  using M = TypeParam;
  using S = DampedOscillator;
  if (Traits<M>::long_time_h == LongTimeH::tested_elsewhere)
    GTEST_SKIP() << "its linear drift law is tested in test_hybrid_leapfrog.cpp";
  const int order = catalog_order<M>();
  const double omega = 1.0, gamma = 0.01, t_end = 1e4;
  const double h = order == 2 ? 0.01 : order == 4 ? 0.05 : 0.2;
  const ParamsOf<S, double> c{omega, gamma};
  LaneState<1> x{};
  x.q[0] = 1.0, x.z = 1.0;
  M::template start<S>(x, c);
  const auto k = M::template coefficients<S>(h, c, x);
  auto H = [&] { return std::exp(x.mu) * K<S>(x.q, x.p, x.z, c); };
  const double H0 = H();
  const long steps = std::llround(t_end / h), quarter = steps / 4;
  double quarter_max[4] = {0, 0, 0, 0}, quarter_end[4] = {0, 0, 0, 0};
  for (long n = 1; n <= steps; ++n) {
    M::template step<S, kAll>(x, c, k);
    const double rel = H() / H0 - 1.0;
    const auto qi = std::min<long>((n - 1) / quarter, 3);
    quarter_max[qi] = std::max(quarter_max[qi], std::fabs(rel));
    if (n % quarter == 0) quarter_end[n / quarter - 1] = rel;
  }
  const double overall = *std::max_element(quarter_max, quarter_max + 4);
  this->RecordProperty("max_rel_H_error", test::full_precision(overall));
  if (Traits<M>::long_time_h == LongTimeH::bounded) {
    const double predicted = predicted_h_amplitude<M>(h, omega, 1.0, 0.0, H0);
    this->RecordProperty("predicted", test::full_precision(predicted));
    // Reaches the bound and never exceeds it; and no secular trend.
    EXPECT_NEAR(overall / predicted, 1.0, 0.03);
    EXPECT_NEAR(quarter_max[3] / quarter_max[0], 1.0, 0.01);
  } else {
    // Not geometric: |ΔH/H| grows linearly (measured −1.8e-5 at t = 10⁴ for RK4, h = 0.05).
    EXPECT_GT(quarter_max[3], 3.0 * quarter_max[0]);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(quarter_end[i] / quarter_end[3], (i + 1) / 4.0, 0.02);
  }
}

// ---- time-dependent K: forcing and damping that change with t ---------------------------------

// Integrates from t0 with the lane's time t0 + n·h (as the kernel sets it) and returns the
// largest errors in q, p and ln λ against `exact` at t0 + 1, …, t0 + 10.
template <class M, class S, class Exact>
Errors time_dependent_errors(double h, const ParamsOf<S, double>& c, double t0, double q0,
                             double p0, Exact exact) {
  LaneState<1> x{};
  x.q[0] = q0, x.p[0] = p0, x.z = 1.0, x.t = t0;
  M::template start<S>(x, c);
  const auto k = M::template coefficients<S>(h, c, x);
  const auto per_unit = std::llround(1.0 / h);
  Errors e{0, 0, 0, 0};
  std::int64_t n = 0;
  for (int unit = 1; unit <= 10; ++unit) {
    for (long i = 0; i < per_unit; ++i, ++n) {
      x.t = t0 + static_cast<double>(n) * h;
      M::template step<S, kAll>(x, c, k);
    }
    const auto ex = exact(t0 + static_cast<double>(n) * h);
    e.q = std::max(e.q, std::fabs(x.q[0] - ex.q));
    e.p = std::max(e.p, std::fabs(x.p[0] - ex.p));
    e.log_lambda = std::max(e.log_lambda, std::fabs(log_lambda<S>(x) - ex.log_lambda));
  }
  return e;
}

// Three halvings; each must show the method's order in q, p and (where it is not exact) ln λ.
// A method that took K at the wrong time in any sub-step would drop to order 1 (a time error
// δt in a force of size F leaves F·δt per step), which ±0.25 tells apart from 2.
template <class M>
void expect_order(const std::vector<Errors>& e, bool log_lambda_exact) {
  const int order = catalog_order<M>();
  for (std::size_t i = 0; i + 1 < e.size(); ++i) {
    SCOPED_TRACE("halving " + std::to_string(i));
    const double tolerance = order == 2 ? 0.1 : 0.25;
    EXPECT_NEAR(std::log2(e[i].q / e[i + 1].q), order, tolerance) << e[i].q << " " << e[i + 1].q;
    EXPECT_NEAR(std::log2(e[i].p / e[i + 1].p), order, tolerance) << e[i].p << " " << e[i + 1].p;
    if (!log_lambda_exact) {
      EXPECT_NEAR(std::log2(e[i].log_lambda / e[i + 1].log_lambda), order, tolerance)
          << e[i].log_lambda << " " << e[i + 1].log_lambda;
    }
  }
}

TYPED_TEST(EveryMethod, ObservedOrderWithTimeDependentForcing) {
  using M = TypeParam;
  using S = test::ForcedOscillator;
  const ParamsOf<S, double> c{1.0, 0.1, 0.5, 1.3};
  const double t0 = 0.7;  // a start away from 0 shows a time that is off by t0
  const int order = catalog_order<M>();
  const double h0 = order == 6 ? 0.2 : 0.1;
  std::vector<Errors> e;
  for (int i = 0; i < 4; ++i)
    e.push_back(time_dependent_errors<M, S>(h0 / (1 << i), c, t0, 1.0, 0.0, [&](double t) {
      return S::exact(c, t0, 1.0, 0.0, t);
    }));
  expect_order<M>(e, Traits<M>::exact_log_lambda);
  if (Traits<M>::exact_log_lambda) {  // K_z = −γ: round-off only, as on scene A
    for (std::size_t i = 0; i < e.size(); ++i)
      EXPECT_LE(e[i].log_lambda, 10.0 / (h0 / (1 << i)) * 0x1p-52);
  }
}

TYPED_TEST(EveryMethod, ObservedOrderWithTimeDependentDamping) {
  using M = TypeParam;
  using S = test::LaneEmden5;
  const double t0 = 1.0;  // the damping 2/t is singular at t = 0
  const auto start = S::exact(t0, t0);
  const int order = catalog_order<M>();
  const double h0 = order == 6 ? 0.2 : 0.1;
  std::vector<Errors> e;
  for (int i = 0; i < 4; ++i)
    e.push_back(time_dependent_errors<M, S>(h0 / (1 << i), {0.0}, t0, start.q, start.p,
                                            [&](double t) { return S::exact(t, t0); }));
  // K_z = −2/t varies. The hybrid leap-frog's factors a = 1 + h/t_n and b = t_n/(t_n + h) give
  // ln a − ln b = 2 ln(t_{n+1}/t_n): ln λ = 2 ln(t/t0) exactly, up to round-off of ≤ 3 logs a
  // step. The other methods approximate ∫2/t with their own order.
  constexpr bool exact = std::is_same_v<M, HybridLeapfrog>;
  expect_order<M>(e, exact);
  if (exact) {
    for (std::size_t i = 0; i < e.size(); ++i)
      EXPECT_LE(e[i].log_lambda, 3.0 * 10.0 / (h0 / (1 << i)) * 0x1p-52);
  }
}

// ---- all methods agree on every scene as h shrinks --------------------------------------------

// The reference is contact_splitting6 at h = 0.001; RK4 at the same h, an independent method,
// must agree with it to 1e-10 (measured ≤ 2e-11), far below the errors being compared (≳ 1e-8).
// Scene B's −γz² part has an exact flow too (split_flows.hpp), so the splitting is a valid
// reference there as well, and RK4 cross-checks that flow.
template <class M, class S>
void expect_convergence_to_reference(const char* scene) {
  SCOPED_TRACE(scene);
  constexpr double h_reference = 0.001;
  const auto reference = states_at_whole_times<ContactSplitting6, S>(h_reference);
  ASSERT_LT(max_distance(reference, states_at_whole_times<Rk4, S>(h_reference)), 1e-10);
  const int order = catalog_order<M>();
  const double h0 = (order == 2 ? 0.04 : order == 4 ? 0.1 : 0.4) * PaperScene<S>::h_scale;
  double e[3];
  for (int i = 0; i < 3; ++i)
    e[i] = max_distance(states_at_whole_times<M, S>(h0 / (1 << i)), reference);
  // On the nonlinear scenes the error constant still varies at these h (RK4 on scene C shows
  // 4.36 then 4.22), hence ±0.3; the last halving is the one asserted.
  EXPECT_NEAR(std::log2(e[1] / e[2]), order, 0.3)
      << "errors " << e[0] << " " << e[1] << " " << e[2];
  EXPECT_LT(e[2], e[0]);
}

TYPED_TEST(EveryMethod, AgreeWithTheReferenceOnEveryScene) {
  expect_convergence_to_reference<TypeParam, DampedOscillator>("damped_oscillator");
  expect_convergence_to_reference<TypeParam, Z2Damping>("z2_damping");
  expect_convergence_to_reference<TypeParam, DoubleWell>("double_well");
  expect_convergence_to_reference<TypeParam, CoupledOscillators>("coupled_oscillators");
}

// ---- the run path: catalog name → dispatch → tiled kernel --------------------------------------

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Each grid point, integrated by the engine, ends with the same bits as direct steps of the
// method with that point's parameters: the name reaches the right kernel, and the kernel (W
// lanes; parameters shared by all lanes, or per lane with a gamma axis) computes exactly the
// scalar step.
template <class M, class S>
void expect_engine_equals_direct_steps(const std::string& scene, const std::string& p_axis,
                                       bool per_lane_parameters) {
  SCOPED_TRACE(scene + (per_lane_parameters ? ", per-lane parameters" : ", uniform parameters"));
  const std::string spec = "[scene]\nname = \"" + scene + "\"\n[integrator]\nmethod = \"" +
                           std::string(M::description.name) + "\"\nh = 0.05\nt_end = 10.0\n[grid]\n" + p_axis +
                           " = { values = [0.0, 0.3, -0.2] }\n" +
                           (per_lane_parameters ? "gamma = { values = [0.05, 0.1] }\n" : "") +
                           "[measures]\nfinal_state = true\n";
  const auto out = test::run_in_memory(spec);
  RunSpec run = parse_run_spec(spec, {}, "test spec");
  RunPlan plan(run, *find_scene(run.scene), *find_method(run.method));
  const auto& vars = plan.scene.variables;  // q.., p.., z, lambda
  for (std::int64_t point = 0; point < plan.grid.size(); ++point) {
    double params[16], state[16];
    plan.grid.point(point, params, state);
    const auto c = S::params_from(params);
    LaneState<S::dof> x{};
    for (int d = 0; d < S::dof; ++d) x.q[d] = state[d], x.p[d] = state[S::dof + d];
    x.z = state[2 * S::dof];
    x.mu = std::log(state[2 * S::dof + 1]);
    M::template start<S>(x, c);
    const auto k = M::template coefficients<S>(run.h, c, x);
    for (std::int64_t n = 0; n < run.steps; ++n) M::template step<S, kAll>(x, c, k);
    const double expected[] = {x.q[0], x.q[S::dof - 1], x.p[0], x.p[S::dof - 1], x.z,
                               log_lambda<S>(x)};
    const int slots[] = {0, S::dof - 1, S::dof, 2 * S::dof - 1, 2 * S::dof, 2 * S::dof + 1};
    for (int i = 0; i < 6; ++i) {
      const auto& name = vars[slots[i]].name;
      const auto dataset = "final_" + (name == "lambda" ? std::string("log_lambda") : name);
      EXPECT_TRUE(same_bits(out.at(dataset)[point], expected[i]))
          << dataset << " at point " << point << ": " << out.at(dataset)[point] << " vs "
          << expected[i];
    }
  }
}

TYPED_TEST(EveryMethod, EngineRunEqualsDirectSteps) {
  for (bool per_lane : {false, true}) {
    using M = TypeParam;
    expect_engine_equals_direct_steps<M, DampedOscillator>("damped_oscillator", "p_0", per_lane);
    expect_engine_equals_direct_steps<M, Z2Damping>("z2_damping", "p_0", per_lane);
    expect_engine_equals_direct_steps<M, DoubleWell>("double_well", "p_0", per_lane);
    expect_engine_equals_direct_steps<M, CoupledOscillators>("coupled_oscillators", "p1_0",
                                                             per_lane);
  }
}

}  // namespace
}  // namespace cs
