// The tangent step (engine/measures/tangent_lyapunov.hpp) for every method, one lane at a time
// (lane_lyapunov: the facility the attractor table's attractor_lyapunov is to use):
//  * scene A, linear: the exponent is (1/T) ln(|M^N v| / |v|), M the method's one-step matrix
//    read off by stepping the unit vectors with the plain double step (support/linear_step_map);
//  * the double well (nonlinear: K's partials on nested duals) and scene B (z feeds back, so
//    the tangent includes δz): the tangent's growth equals the central difference of the plain
//    step map iterated N times, to the difference's O(ε²);
//  * the value part of the dual step is the plain step, bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "engine/measures/tangent_lyapunov.hpp"
#include "numerics/method_list.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/dual_math.hpp"
#include "physics/double_well.hpp"
#include "physics/z2_damping.hpp"
#include "support/all_methods.hpp"
#include "support/linear_step_map.hpp"

namespace cs::test {
namespace {

// A scene whose potential calls every elementary function a K may use, so that the nested-dual
// versions (physics/dual_math_nested.hpp) are exercised: K = p²/2 + V(q) − γz with
// V = −cos q + sin(q)/4 + √(1+q²)/10 + e^{q/5}/20 + log(2+q²)/20 + tanh(q)/10 + atan(q)/10
//     + asin(q/9)/10 + acos(q/9)/10 + tan(q/7)/20 + sinh(q/5)/20 + cosh(q/5)/20 + |q|³/100
//     + (1+q²)^1.5/100 + 2^(q/8)/10 + (1+q²)^(q/10)/100.
struct AllFunctions {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = false;
  static constexpr bool kz_constant = true;
  static constexpr ZPart z_part = ZPart::linear;
  template <class T>
  struct Params {
    T gamma;
  };
  template <class T>
  static Params<T> params_from(const T* v) {
    return {v[0]};
  }
  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    const auto q0 = q<0>(x);
    const auto r = 1.0 + square(q0);
    const auto v = -cos(q0) + 0.25 * sin(q0) + 0.1 * sqrt(r) + 0.05 * exp(0.2 * q0) +
                   0.05 * log(1.0 + r) + 0.1 * tanh(q0) + 0.1 * atan(q0) + 0.1 * asin(q0 / 9.0) +
                   0.1 * acos(q0 / 9.0) + 0.05 * tan(q0 / 7.0) + 0.05 * sinh(0.2 * q0) +
                   0.05 * cosh(0.2 * q0) + 0.01 * (abs(q0) * square(q0)) + 0.01 * pow(r, 1.5) +
                   0.1 * pow(2.0, 0.125 * q0) + 0.01 * pow(r, 0.1 * q0);
    return half_square(p<0>(x)) + v - c.gamma * z(x);
  }
  static bool diverged(const double*, const double*) { return false; }
};

template <class Method>
class LaneLyapunov : public ::testing::Test {};
TYPED_TEST_SUITE(LaneLyapunov, AllMethods);

template <Scene S, class Method, Carry carry>
LaneState<S::dof> started(const ParamsOf<S, double>& c, double q, double p, double z) {
  LaneState<S::dof> x{};
  x.q[0] = q, x.p[0] = p, x.z = z;
  Method::template start<S>(x, c);
  return x;
}

// N plain steps of the method from (q, p, z): the end state.
template <Scene S, class Method, Carry carry>
LaneState<S::dof> plain_steps(const ParamsOf<S, double>& c, double q, double p, double z, double h,
                              int n) {
  LaneState<S::dof> x = started<S, Method, carry>(c, q, p, z);
  const auto k = Method::template coefficients<S>(h, c, x);
  for (int s = 0; s < n; ++s) Method::template step<S, carry>(x, c, k);
  return x;
}

// (1/T) ln of |Φ^N(x + εv) − Φ^N(x − εv)| / (2ε|v|), over the components the tangent holds.
template <Scene S, class Method, Carry carry>
double difference_exponent(const ParamsOf<S, double>& c, double q, double p, double z,
                           const double* v, double h, int n) {
  const double eps = 1e-6;
  const auto a =
      plain_steps<S, Method, carry>(c, q + eps * v[0], p + eps * v[1], z + eps * v[2], h, n);
  const auto b =
      plain_steps<S, Method, carry>(c, q - eps * v[0], p - eps * v[1], z - eps * v[2], h, n);
  double d2 = std::pow(a.q[0] - b.q[0], 2) + std::pow(a.p[0] - b.p[0], 2);
  double v2 = v[0] * v[0] + v[1] * v[1];
  if constexpr (tangent_has_z<S>()) d2 += std::pow(a.z - b.z, 2), v2 += v[2] * v[2];
  return std::log(std::sqrt(d2) / (2 * eps * std::sqrt(v2))) / (n * h);
}

TYPED_TEST(LaneLyapunov, DampedOscillatorIsTheStepMatrixPower) {
  using Method = TypeParam;
  using S = DampedOscillator;
  const double omega = 1.0, gamma = 0.1, h = 0.01;
  const int n = 2000;
  const Eigen::Matrix2d m = one_step_matrix<Method>(h, omega, gamma);
  Eigen::Matrix2d power = Eigen::Matrix2d::Identity();
  for (int s = 0; s < n; ++s) power = m * power;
  const Eigen::Vector2d v(1.0, 1.0);
  const double expected = std::log((power * v).norm() / v.norm()) / (n * h);
  const ParamsOf<S, double> c{omega, gamma};
  LaneState<1> x = started<S, Method, Carry{false, false}>(c, 1.0, 0.0, 0.0);
  const double value = lane_lyapunov<S, Method, Carry{false, false}>(x, c, n, h, {1.0, 1.0, 0.0},
                                                                     0.5 * std::log(2.0));
  // Rounding alone: n steps of relative error ~1e-16 in the tangent and in M^N.
  EXPECT_NEAR(value, expected, 1e-12) << Method::description.name;
  // and the flow's −γ/2 to within ln(cond V)/T (V: eigenvectors; cond ≈ 1.1 here) + O(h^order)
  EXPECT_NEAR(value, -gamma / 2, 0.1 / (n * h) + 1e-3);
}

TYPED_TEST(LaneLyapunov, DoubleWellTangentIsTheStepMapsDerivative) {
  using Method = TypeParam;
  using S = DoubleWell;
  const ParamsOf<S, double> c{1.0, 0.1};
  const double v[3] = {1.0, 1.0, 0.0}, h = 0.01;
  const int n = 500;
  LaneState<1> x = started<S, Method, Carry{false, false}>(c, 0.3, 0.8, 0.0);
  const double value = lane_lyapunov<S, Method, Carry{false, false}>(x, c, n, h, {1.0, 1.0, 0.0},
                                                                     0.5 * std::log(2.0));
  const double expected =
      difference_exponent<S, Method, Carry{false, false}>(c, 0.3, 0.8, 0.0, v, h, n);
  // Central differences: O(ε²) relative (ε = 1e-6) plus rounding ~1e-16/ε = 1e-10, over T = 5.
  EXPECT_NEAR(value, expected, 1e-8) << Method::description.name;
  // The lane's end state is the plain step's, bit for bit.
  const auto plain = plain_steps<S, Method, Carry{false, false}>(c, 0.3, 0.8, 0.0, h, n);
  EXPECT_EQ(x.q[0], plain.q[0]);
  EXPECT_EQ(x.p[0], plain.p[0]);
}

TYPED_TEST(LaneLyapunov, EveryFunctionOfKOnNestedDuals) {
  using Method = TypeParam;
  using S = AllFunctions;
  const ParamsOf<S, double> c{0.05};
  const double v[3] = {1.0, 1.0, 0.0}, h = 0.01;
  const int n = 500;
  LaneState<1> x = started<S, Method, Carry{false, false}>(c, 0.7, 0.4, 0.0);
  const double value = lane_lyapunov<S, Method, Carry{false, false}>(x, c, n, h, {1.0, 1.0, 0.0},
                                                                     0.5 * std::log(2.0));
  const double expected =
      difference_exponent<S, Method, Carry{false, false}>(c, 0.7, 0.4, 0.0, v, h, n);
  EXPECT_NEAR(value, expected, 1e-8) << Method::description.name;
  const auto plain = plain_steps<S, Method, Carry{false, false}>(c, 0.7, 0.4, 0.0, h, n);
  EXPECT_EQ(x.q[0], plain.q[0]);
  EXPECT_EQ(x.p[0], plain.p[0]);
}

TYPED_TEST(LaneLyapunov, ZFeedingBackJoinsTheTangent) {
  using Method = TypeParam;
  using S = Z2Damping;
  static_assert(tangent_has_z<S>());
  const ParamsOf<S, double> c{1.0, 0.1};
  const double v[3] = {1.0, 1.0, 1.0}, h = 0.01;
  const int n = 500;
  LaneState<1> x = started<S, Method, Carry{true, false}>(c, 1.0, 0.0, 0.5);
  const double value = lane_lyapunov<S, Method, Carry{true, false}>(x, c, n, h, {1.0, 1.0, 1.0},
                                                                    0.5 * std::log(3.0));
  const double expected =
      difference_exponent<S, Method, Carry{true, false}>(c, 1.0, 0.0, 0.5, v, h, n);
  EXPECT_NEAR(value, expected, 1e-8) << Method::description.name;
  const auto plain = plain_steps<S, Method, Carry{true, false}>(c, 1.0, 0.0, 0.5, h, n);
  EXPECT_EQ(x.z, plain.z);
}

}  // namespace
}  // namespace cs::test
