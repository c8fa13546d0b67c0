// The exactly solvable parts of a separable contact Hamiltonian K = Σ p_i²/2 + V(q) + Z(z) and
// their exact flows, in the paper's convention q' = K_p, p' = −K_q + pK_z, z' = K − pK_p,
// (ln λ)' = −K_z (Bravetti, Seri, Vermeeren, Zadra 2020; shared/PHYSICS.md):
//
//   p²/2:   q += t·p,            z −= t·p²/2
//   V(q):   p −= t·V′(q),        z += t·V(q)
//   k·z:    p ×= e^{kt},         z ×= e^{kt},     ln λ −= k·t
//   k·z²:   s = 1 − k·z₀·t,      z = z₀/s,        p ×= 1/s²,   ln λ += 2 ln s
//
// The last one, derived: z' = kz² gives z = z₀/(1 − kz₀t); then (ln p)' = K_z = 2kz = −(ln s)'·2
// and (ln λ)' = −2kz = 2(ln s)'. It leaves the real line where s ≤ 0 (the exact sub-flow itself
// blows up; for scene B, k = −γ, that is z₀ < −1/(γt)), which the step reports as breakdown.
//
// V, V′ and k are read off the scene's own K: K(q, 0, 0) = V(q) and K_q(q, 0, 0) = V′(q), since
// Z(0) = 0 and the kinetic part vanishes at p = 0; k = K_z(0, 0, 0) for a linear Z and
// K_z(0, 0, 1)/2 for a quadratic one. tests/test_methods.cpp checks that each splittable scene
// is the sum of these parts.
//
// A time-dependent K = Σ p²/2 + V(q, t) + c(t)·z (or c(t)·z²) is split the same way in the
// extended phase space where t is a coordinate advanced by the kinetic flow (t += τ with q):
// the V and Z flows see t frozen, so they stay exact and the compositions keep their orders.
#pragma once

#include <cmath>

#include "numerics/lane_math.hpp"
#include "numerics/lane_state.hpp"
#include "physics/partials.hpp"

namespace cs {

template <class T>
constexpr T value_of(T x) {
  return x;
}
template <class T>
constexpr T value_of(Dual<T> x) {
  return x.v;
}

// V(q) and ∂V/∂q_i from one evaluation of K with q_i seeded (its value part is V itself).
template <SplittableScene S, int i, class T, class C>
inline void potential_and_force(const T* q, const C& c, T t, T& v, T& force) {
  T zero[S::dof] = {};
  auto k = S::K(StateView<T, Seed::q, i>{q, zero, T{}, t}, c);
  v = value_of<T>(k);
  force = derivative<T>(k);
}

template <SplittableScene S, class T, class C>
inline T potential(const T* q, const C& c, T t) {
  T zero[S::dof] = {};
  return K<S>(q, zero, T{}, c, t);
}

template <SplittableScene S, int i, class T, class C>
inline T potential_force(const T* q, const C& c, T t) {
  T zero[S::dof] = {};
  return K_q<S, i>(q, zero, T{}, c, t);
}

// k in Z(z) = k·z or k·z² (k may depend on t).
template <SplittableScene S, class T, class C>
inline T z_coefficient(const C& c, T t) {
  T zero[S::dof] = {};
  if constexpr (S::z_part == ZPart::linear)
    return K_z<S>(zero, zero, T{}, c, t);
  else
    return 0.5 * K_z<S>(zero, zero, T{} + 1.0, c, t);
}

// ---- the flows; `with_z` says whether z is integrated at all -----------------------------------

// The flows' lengths and factors (P) are T, or plain doubles in a tangent step (T a dual).
template <bool with_z, int D, class T, class P>
inline void kinetic_flow(LaneState<D, T>& x, P t) {
  for (int i = 0; i < D; ++i) {
    if constexpr (with_z) x.z = lane_math::mul_add(-t, half_square(x.p[i]), x.z);
    x.q[i] = lane_math::mul_add(t, x.p[i], x.q[i]);
  }
}

// `force` and `v` are V′ and V at the current q (a kick leaves q alone, so they stay valid).
template <bool with_z, int D, class T, class P>
inline void potential_flow(LaneState<D, T>& x, P t, const T* force, T v) {
  for (int i = 0; i < D; ++i) x.p[i] = lane_math::mul_add(-t, force[i], x.p[i]);
  if constexpr (with_z) x.z = lane_math::mul_add(t, v, x.z);
}

// Z = k·z for time t, given decay = e^{kt}; ln λ is advanced once per step by the caller.
template <bool with_z, int D, class T, class P>
inline void linear_z_flow(LaneState<D, T>& x, P decay) {
  for (int i = 0; i < D; ++i) x.p[i] = x.p[i] * decay;
  if constexpr (with_z) x.z = x.z * decay;
}

// Z = k·z² for time t (z always feeds back here).
template <bool with_mu, int D, class T, class K, class P>
inline void quadratic_z_flow(LaneState<D, T>& x, K k, P t) {
  T s = 1.0 - k * x.z * t;
  x.broken += (s <= 0.0);
  T r = 1.0 / s;
  x.z = x.z * r;
  for (int i = 0; i < D; ++i) x.p[i] = x.p[i] * (r * r);
  if constexpr (with_mu) x.mu = x.mu + 2.0 * lane_math::log(s);
}

}  // namespace cs
