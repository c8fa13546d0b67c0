// Elementary functions of doubles and of dual numbers, and division of dual numbers, for scenes
// written as formulas. Inside namespace cs an unqualified sin(x) finds these overloads (ordinary
// lookup stops at cs, so ::sin from <cmath> is never considered); values come from
// numerics/lane_math.hpp, which vectorises and gives the same bits on every path, and the
// derivative follows by the chain rule. Only Dual<double> is supported (the lane loop vectorises
// over doubles); overloads are plain functions, not templates, so that pow(x, 2) converts 2.
#pragma once

#include "numerics/lane_math.hpp"
#include "numerics/lane_math_dual.hpp"
#include "physics/dual.hpp"

namespace cs {

// (a/b)' = (a' − (a/b)·b')·(1/b), with the value itself rounded once. Derivatives multiply by
// the reciprocal 1/b instead of dividing: it depends on the value alone, so the compiler computes
// it once for every partial (K_q1, K_q2, ... evaluate K once per seed) and for 1/b itself, and a
// division costs 8-16 multiplications' time. The magnetic pendulum's force went from 15 divisions
// to 3 (45 to 21 ns a lane-step, README "Benchmarks"); the derivative is rounded twice (~1 ulp).
template <class T>
constexpr Dual<T> operator/(Dual<T> a, Dual<T> b) {
  const T v = a.v / b.v, inverse = 1.0 / b.v;
  return {v, lane_math::mul_add(-v, b.d, a.d) * inverse};
}
template <class T>
constexpr Dual<T> operator/(Dual<T> a, T c) {
  return {a.v / c, a.d / c};
}
template <class T>
constexpr Dual<T> operator/(T c, Dual<T> b) {
  const T v = c / b.v, inverse = 1.0 / b.v;
  return {v, -(v * b.d) * inverse};
}

[[gnu::always_inline]] inline double sqrt(double x) { return lane_math::sqrt(x); }
[[gnu::always_inline]] inline double abs(double x) { return lane_math::abs(x); }
[[gnu::always_inline]] inline double exp(double x) { return lane_math::exp(x); }
[[gnu::always_inline]] inline double log(double x) { return lane_math::log(x); }
[[gnu::always_inline]] inline double sin(double x) { return lane_math::sin(x); }
[[gnu::always_inline]] inline double cos(double x) { return lane_math::cos(x); }
[[gnu::always_inline]] inline double tan(double x) { return lane_math::tan(x); }
[[gnu::always_inline]] inline double sinh(double x) { return lane_math::sinh(x); }
[[gnu::always_inline]] inline double cosh(double x) { return lane_math::cosh(x); }
[[gnu::always_inline]] inline double tanh(double x) { return lane_math::tanh(x); }
[[gnu::always_inline]] inline double asin(double x) { return lane_math::asin(x); }
[[gnu::always_inline]] inline double acos(double x) { return lane_math::acos(x); }
[[gnu::always_inline]] inline double atan(double x) { return lane_math::atan(x); }
[[gnu::always_inline]] inline double pow(double x, double y) { return lane_math::pow(x, y); }

// (√x)' = x'/(2√x), as (x'/2)·(1/√x): the reciprocal is the one a 1/√x around it needs too.
[[gnu::always_inline]] inline Dual<double> sqrt(Dual<double> x) {
  const double r = lane_math::sqrt(x.v);
  return {r, (0.5 * x.d) * (1.0 / r)};
}
// |x|' = ±x', taken as +x' at x = 0.
[[gnu::always_inline]] inline Dual<double> abs(Dual<double> x) {
  return {lane_math::abs(x.v), lane_math::select(x.v < 0.0, -x.d, x.d)};
}
[[gnu::always_inline]] inline Dual<double> exp(Dual<double> x) {
  const double e = lane_math::exp(x.v);
  return {e, e * x.d};
}
[[gnu::always_inline]] inline Dual<double> log(Dual<double> x) {
  return {lane_math::log(x.v), x.d / x.v};
}
// sin and cos of the same argument share their reduction once inlined (GCC merges it).
[[gnu::always_inline]] inline Dual<double> sin(Dual<double> x) {
  return {lane_math::sin(x.v), lane_math::cos(x.v) * x.d};
}
[[gnu::always_inline]] inline Dual<double> cos(Dual<double> x) {
  return {lane_math::cos(x.v), -(lane_math::sin(x.v) * x.d)};
}
[[gnu::always_inline]] inline Dual<double> tan(Dual<double> x) {
  const double t = lane_math::tan(x.v);
  return {t, (1.0 + t * t) * x.d};
}
[[gnu::always_inline]] inline Dual<double> sinh(Dual<double> x) {
  return {lane_math::sinh(x.v), lane_math::cosh(x.v) * x.d};
}
[[gnu::always_inline]] inline Dual<double> cosh(Dual<double> x) {
  return {lane_math::cosh(x.v), lane_math::sinh(x.v) * x.d};
}
// tanh' = 1/cosh², not 1 − tanh², which cancels to 0 once tanh rounds to ±1 (|x| > 19).
[[gnu::always_inline]] inline Dual<double> tanh(Dual<double> x) {
  const double c = lane_math::cosh(x.v);
  return {lane_math::tanh(x.v), x.d / (c * c)};
}
// 1 − x² as (1 − x)(1 + x): exact factors near |x| = 1, where the derivative is largest.
[[gnu::always_inline]] inline Dual<double> asin(Dual<double> x) {
  return {lane_math::asin(x.v), x.d / lane_math::sqrt((1.0 - x.v) * (1.0 + x.v))};
}
[[gnu::always_inline]] inline Dual<double> acos(Dual<double> x) {
  return {lane_math::acos(x.v), -(x.d / lane_math::sqrt((1.0 - x.v) * (1.0 + x.v)))};
}
[[gnu::always_inline]] inline Dual<double> atan(Dual<double> x) {
  return {lane_math::atan(x.v), x.d / (1.0 + x.v * x.v)};
}

// (x^y)' = y·x^(y−1)·x' + x^y·log x·y'. Written with x^(y−1) rather than x^y/x so that x = 0
// gives 0, not NaN, for y > 1; a constant exponent y = 0 gives 0, and x^y = 0 (x = 0, y > 0)
// makes the log x term 0.
namespace dual_math_detail {
[[gnu::always_inline]] inline double pow_dx(double x, double y) {
  return lane_math::select(y == 0.0, 0.0, y * lane_math::pow(x, y - 1.0));
}
[[gnu::always_inline]] inline double pow_dy(double v, double x) {
  return lane_math::select(v == 0.0, 0.0, v * lane_math::log(x));
}
}  // namespace dual_math_detail

[[gnu::always_inline]] inline Dual<double> pow(Dual<double> x, double y) {
  return {lane_math::pow(x.v, y), dual_math_detail::pow_dx(x.v, y) * x.d};
}
[[gnu::always_inline]] inline Dual<double> pow(double x, Dual<double> y) {
  const double v = lane_math::pow(x, y.v);
  return {v, dual_math_detail::pow_dy(v, x) * y.d};
}
[[gnu::always_inline]] inline Dual<double> pow(Dual<double> x, Dual<double> y) {
  const double v = lane_math::pow(x.v, y.v);
  return {v, dual_math_detail::pow_dx(x.v, y.v) * x.d + dual_math_detail::pow_dy(v, x.v) * y.d};
}

}  // namespace cs

#include "physics/dual_math_nested.hpp"  // the same on Dual<Dual<double>>
