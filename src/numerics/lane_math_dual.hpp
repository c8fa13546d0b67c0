// lane_math's operations on dual numbers, so that an integrator's own step, written once as a
// template over its number type, runs with T = Dual<double>: the value part is the step itself
// (each value is computed by the very operations, in the same order, as with T = double: same
// bits) and the derivative part is the exact linearisation of the step applied to the seeded
// tangent vector (engine/measures/tangent_lyapunov.hpp). The partials K_q, K_p, K_z inside the
// step then evaluate K on Dual<Dual<double>> (physics/dual_math_nested.hpp).
//
// Declared before the methods' templates (lane_state.hpp includes this file): they call
// `lane_math::mul_add` qualified, which finds only overloads declared before the template.
// Derivatives of constants (a double argument) are 0 and cost nothing.
#pragma once

#include <type_traits>

#include "numerics/lane_math.hpp"
#include "physics/dual.hpp"

namespace cs {

// Comparisons look at values (a branch-free step compares λ factors: hybrid_leapfrog.hpp).
template <class T>
constexpr bool operator<(Dual<T> a, Dual<T> b) {
  return a.v < b.v;
}
template <class T>
constexpr bool operator<=(Dual<T> a, double c) {
  return a.v <= c;
}
template <class T>
constexpr bool operator<(Dual<T> a, double c) {
  return a.v < c;
}
template <class T>
constexpr bool operator>(Dual<T> a, double c) {
  return a.v > c;
}
// A breakdown counter (LaneState::broken) counts in its value.
template <class T, class N>
requires std::is_arithmetic_v<N>
constexpr Dual<T>& operator+=(Dual<T>& a, N n) {
  a.v += n;
  return a;
}

namespace lane_math {

// (a·b + c)' = a·b' + a'·b + c', each part fused once more.
template <class T>
[[gnu::always_inline]] inline Dual<T> mul_add(Dual<T> a, Dual<T> b, Dual<T> c) {
  return {mul_add(a.v, b.v, c.v), mul_add(a.v, b.d, mul_add(a.d, b.v, c.d))};
}
template <class T>
[[gnu::always_inline]] inline Dual<T> mul_add(double a, Dual<T> b, Dual<T> c) {
  return {mul_add(a, b.v, c.v), mul_add(a, b.d, c.d)};
}
template <class T>
[[gnu::always_inline]] inline Dual<T> mul_add(Dual<T> a, Dual<T> b, double c) {
  return {mul_add(a.v, b.v, c), mul_add(a.v, b.d, a.d * b.v)};
}
template <class T>
[[gnu::always_inline]] inline Dual<T> mul_add(double a, Dual<T> b, double c) {
  return {mul_add(a, b.v, c), a * b.d};
}
template <class T>
[[gnu::always_inline]] inline Dual<T> select(bool c, Dual<T> a, Dual<T> b) {
  return {select(c, a.v, b.v), select(c, a.d, b.d)};
}
template <class T>
[[gnu::always_inline]] inline Dual<T> exp(Dual<T> x) {
  const T e = exp(x.v);
  return {e, e * x.d};
}
template <class T>
[[gnu::always_inline]] inline Dual<T> log(Dual<T> x) {
  return {log(x.v), x.d / x.v};
}

}  // namespace lane_math
}  // namespace cs
