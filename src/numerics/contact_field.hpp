// The full contact vector field as the Runge–Kutta methods (rk4, dop853) see it:
//   q' = K_p,  p' = −K_q + p·K_z,  z' = K − Σ p_i K_{p_i},  (ln λ)' = −K_z
// on a point of the extended state, with the partials derived from the scene's K. z and ln λ
// take part only where the instantiation integrates them (with_z, with_mu).
#pragma once

#include <utility>

#include "numerics/lane_math.hpp"
#include "numerics/lane_state.hpp"
#include "physics/partials.hpp"

namespace cs::contact_field {

// f(integral_constant<int, i>) for i = 0 … N − 1, forced inline all the way down: for_each_dof
// with no inlining heuristics in between (a step of 12 rates exceeds GCC's stack-frame limits,
// and a call left in the lane loop stops it vectorising).
template <int N, class F>
[[gnu::always_inline]] inline void unrolled(F&& f) {
  [&]<int... i>(std::integer_sequence<int, i...>) __attribute__((always_inline)) {
    (f(std::integral_constant<int, i>{}), ...);
  }(std::make_integer_sequence<int, N>{});
}

// A point of the extended state, or a rate of change of one.
template <int D, class T>
struct Point {
  T q[D], p[D], z, mu;
  Point() = default;
  explicit Point(const LaneState<D, T>& x) : z(x.z), mu(x.mu) {
    for (int i = 0; i < D; ++i) q[i] = x.q[i], p[i] = x.p[i];
  }
};

// y + a·r, fused
template <bool with_z, bool with_mu, int D, class T>
[[gnu::always_inline]] inline Point<D, T> axpy(const Point<D, T>& y, T a, const Point<D, T>& r) {
  using lane_math::mul_add;
  Point<D, T> out;
  for (int i = 0; i < D; ++i) {
    out.q[i] = mul_add(a, r.q[i], y.q[i]);
    out.p[i] = mul_add(a, r.p[i], y.p[i]);
  }
  out.z = with_z ? mul_add(a, r.z, y.z) : y.z;
  out.mu = with_mu ? mul_add(a, r.mu, y.mu) : y.mu;
  return out;
}

// c: the scene's parameters, in T or as plain doubles (the tangent step's, tangent_lyapunov.hpp).
template <Scene S, bool with_z, bool with_mu, class T, class C>
[[gnu::always_inline]] inline Point<S::dof, T> rate(const Point<S::dof, T>& y, const C& c, T t) {
  Point<S::dof, T> r;
  const T kz = K_z<S>(y.q, y.p, y.z, c, t);
  T z_rate{};
  if constexpr (with_z) z_rate = K<S>(y.q, y.p, y.z, c, t);
  unrolled<S::dof>([&](auto i) __attribute__((always_inline)) {
    T kp = K_p<S, i>(y.q, y.p, y.z, c, t);
    r.q[i] = kp;
    r.p[i] = lane_math::mul_add(y.p[i], kz, -K_q<S, i>(y.q, y.p, y.z, c, t));
    if constexpr (with_z) z_rate = lane_math::mul_add(-y.p[i], kp, z_rate);
  });
  r.z = z_rate;
  r.mu = -kz;
  return r;
}

}  // namespace cs::contact_field
