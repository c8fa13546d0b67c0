// dual_math.hpp's functions on nested duals, Dual<Dual<double>>: a scene's K evaluated inside a
// tangent step (numerics/lane_math_dual.hpp), where the outer dual seeds one partial (K_q_i) and
// the inner one carries the tangent vector. Each is the Dual<double> formula written once more
// over T = Dual<double>, in the same order, so that the value part of every result has the bits
// of the plain partial and the tangent part is its exact derivative.
#pragma once

#include <type_traits>

namespace cs {

template <class T>
concept NestedDual = !std::is_same_v<T, double>;

template <NestedDual T>
constexpr Dual<T> operator/(Dual<T> a, double c) {
  return {a.v / c, a.d / c};
}
template <NestedDual T>
constexpr Dual<T> operator/(double c, Dual<T> b) {
  const T v = c / b.v, inverse = 1.0 / b.v;
  return {v, -(v * b.d) * inverse};
}

template <NestedDual T>
inline Dual<T> sqrt(Dual<T> x) {
  const T r = sqrt(x.v);
  return {r, (0.5 * x.d) * (1.0 / r)};
}
template <NestedDual T>
inline Dual<T> abs(Dual<T> x) {
  return {abs(x.v), lane_math::select(x.v.v < 0.0, -x.d, x.d)};
}
template <NestedDual T>
inline Dual<T> exp(Dual<T> x) {
  const T e = exp(x.v);
  return {e, e * x.d};
}
template <NestedDual T>
inline Dual<T> log(Dual<T> x) {
  return {log(x.v), x.d / x.v};
}
template <NestedDual T>
inline Dual<T> sin(Dual<T> x) {
  return {sin(x.v), cos(x.v) * x.d};
}
template <NestedDual T>
inline Dual<T> cos(Dual<T> x) {
  return {cos(x.v), -(sin(x.v) * x.d)};
}
template <NestedDual T>
inline Dual<T> tan(Dual<T> x) {
  const T t = tan(x.v);
  return {t, (1.0 + t * t) * x.d};
}
template <NestedDual T>
inline Dual<T> sinh(Dual<T> x) {
  return {sinh(x.v), cosh(x.v) * x.d};
}
template <NestedDual T>
inline Dual<T> cosh(Dual<T> x) {
  return {cosh(x.v), sinh(x.v) * x.d};
}
template <NestedDual T>
inline Dual<T> tanh(Dual<T> x) {
  const T c = cosh(x.v);
  return {tanh(x.v), x.d / (c * c)};
}
template <NestedDual T>
inline Dual<T> asin(Dual<T> x) {
  return {asin(x.v), x.d / sqrt((1.0 - x.v) * (1.0 + x.v))};
}
template <NestedDual T>
inline Dual<T> acos(Dual<T> x) {
  return {acos(x.v), -(x.d / sqrt((1.0 - x.v) * (1.0 + x.v)))};
}
template <NestedDual T>
inline Dual<T> atan(Dual<T> x) {
  return {atan(x.v), x.d / (1.0 + x.v * x.v)};
}

// pow's two partials (dual_math_detail) on a dual value: the same selects, on values.
namespace dual_math_detail {
template <NestedDual T>
inline T pow_dx(T x, double y) {
  return lane_math::select(y == 0.0, T{} + 0.0, y * pow(x, y - 1.0));
}
template <NestedDual T>
inline T pow_dx(T x, T y) {
  return lane_math::select(y.v == 0.0, T{} + 0.0, y * pow(x, y - 1.0));
}
template <NestedDual T>
inline T pow_dy(T v, T x) {
  return lane_math::select(v.v == 0.0, T{} + 0.0, v * log(x));
}
template <NestedDual T>
inline T pow_dy(T v, double x) {
  return lane_math::select(v.v == 0.0, T{} + 0.0, v * log(x));
}
}  // namespace dual_math_detail

template <NestedDual T>
inline Dual<T> pow(Dual<T> x, double y) {
  return {pow(x.v, y), dual_math_detail::pow_dx(x.v, y) * x.d};
}
template <NestedDual T>
inline Dual<T> pow(double x, Dual<T> y) {
  const T v = pow(x, y.v);
  return {v, dual_math_detail::pow_dy(v, x) * y.d};
}
template <NestedDual T>
inline Dual<T> pow(Dual<T> x, Dual<T> y) {
  const T v = pow(x.v, y.v);
  return {v, dual_math_detail::pow_dx(x.v, y.v) * x.d + dual_math_detail::pow_dy(v, x.v) * y.d};
}
// A nested dual to the power of a plain dual (the exponent a parameter: Params<Dual<double>>).
template <NestedDual T>
inline Dual<T> pow(Dual<T> x, T y) {
  return pow(x, Dual<T>{y, T{}});
}
template <NestedDual T>
inline Dual<T> pow(T x, Dual<T> y) {
  return pow(Dual<T>{x, T{}}, y);
}

}  // namespace cs
