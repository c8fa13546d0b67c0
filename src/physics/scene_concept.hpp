// The scene concept: what a physical system provides so that the kernel can integrate it.
//
// A scene is a type S with
//   static constexpr int dof;              number of (q, p) pairs
//   static constexpr bool z_feeds_back;    does z enter K_q, K_p or K_z? If not, the kernel
//                                          carries z only when a measure asks for it.
//   static constexpr bool kz_constant;     is K_z a constant? Then the λ factors need no log.
//   template <class T> struct Params;      its parameters; T is double or a pack of lanes
//   template <class T> static Params<T> params_from(const T* values);   in catalog order
//   template <class X, class T> static auto K(const X& x, const Params<T>&);
//        the contact Hamiltonian, written once, reading the state through q<i>(x), p<i>(x), z(x)
//   static bool diverged(const double* q, const double* p);   past the scene's bound?
// and optionally
//   static constexpr bool p_in_forces = true      when K_q or K_z depend on p;
//   static constexpr bool time_dependent = true   when K reads the time t(x).
//   static void natural_frequencies(const Params<double>& c, double* omega)
//        ω per degree of freedom: the default frequencies of measures.sync, which scale p_k in
//        the phase θ_k = atan2(−p_k/ω_k, q_k) (1 without it).
// A lane's time is t_start + n·h from its own step count n (never accumulated), so it is the same
// bits wherever the lane runs; each method evaluates K at the times its derivation asks for.
//
// A scene whose K = Σ p_i²/2 + V(q) + Z(z) splits into exactly solvable flows declares the shape
// of its z part, `static constexpr ZPart z_part` (Z = k·z or k·z²); splitting methods read V, its
// force and k off K itself (numerics/split_flows.hpp), so it writes no further formula.
//
// Partials are never written by hand: partials.hpp evaluates K on a state view in which exactly
// one variable is a dual number, so K_q, K_p and K_z come from one formula, and a term that does
// not depend on the seeded variable stays a plain number that costs nothing.
// The run-time description (names, defaults, the paper's values) is in scene_catalog.cpp.
#pragma once

#include <concepts>

#include "physics/dual.hpp"

namespace cs {

// The variable a state view seeds with derivative 1; all others are plain numbers.
enum class Seed { none, q, p, z };

// A read-only view of one lane's (or one pack's) state; `I` is the seeded degree of freedom.
template <class T, Seed S = Seed::none, int I = 0>
struct StateView {
  const T* q;
  const T* p;
  T z;
  T t;  // the time; never seeded (no method needs K_t)
};

template <int i, class T, Seed S, int I>
constexpr auto q(const StateView<T, S, I>& x) {
  if constexpr (S == Seed::q && I == i) return Dual<T>{x.q[i], T{} + 1.0};
  else return x.q[i];
}
template <int i, class T, Seed S, int I>
constexpr auto p(const StateView<T, S, I>& x) {
  if constexpr (S == Seed::p && I == i) return Dual<T>{x.p[i], T{} + 1.0};
  else return x.p[i];
}
template <class T, Seed S, int I>
constexpr auto z(const StateView<T, S, I>& x) {
  if constexpr (S == Seed::z) return Dual<T>{x.z, T{} + 1.0};
  else return x.z;
}

template <class T, Seed S, int I>
constexpr T t(const StateView<T, S, I>& x) {
  return x.t;
}

template <class S>
concept Scene = requires(const double* x, typename S::template Params<double> prm) {
  { S::dof } -> std::convertible_to<int>;
  { S::z_feeds_back } -> std::convertible_to<bool>;
  { S::kz_constant } -> std::convertible_to<bool>;
  { S::params_from(x) } -> std::same_as<typename S::template Params<double>>;
  { S::K(StateView<double>{x, x, 0.0, 0.0}, prm) } -> std::convertible_to<double>;
  { S::diverged(x, x) } -> std::same_as<bool>;
};

enum class ZPart { linear, quadratic };

template <class S>
concept SplittableScene = Scene<S> && requires {
  { S::z_part } -> std::convertible_to<ZPart>;
};

template <Scene S>
constexpr bool p_in_forces() {
  if constexpr (requires { S::p_in_forces; }) return S::p_in_forces;
  else return false;
}

template <Scene S>
constexpr bool time_dependent() {
  if constexpr (requires { S::time_dependent; }) return S::time_dependent;
  else return false;
}

// ω_k for the sync measure's phases: the scene's own (natural_frequencies), else 1.
template <Scene S>
void natural_frequencies(const typename S::template Params<double>& c, double* omega) {
  if constexpr (requires { S::natural_frequencies(c, omega); }) S::natural_frequencies(c, omega);
  else
    for (int k = 0; k < S::dof; ++k) omega[k] = 1.0;
}

template <Scene S, class T>
using ParamsOf = typename S::template Params<T>;

}  // namespace cs
