// K and its partials K_q, K_p, K_z for any scene, derived from the scene's single formula for K
// by forward-mode differentiation (see scene_concept.hpp). T is double or a pack of lanes; t is
// the time, read only by time-dependent scenes.
#pragma once

#include <utility>

#include "physics/scene_concept.hpp"

namespace cs {

template <class T> constexpr T derivative(T) { return T{}; }  // K does not involve the seed
template <class T> constexpr T derivative(Dual<T> x) { return x.d; }

template <Scene S, class T, class C>
inline T K(const T* q, const T* p, T z, const C& c, T t = T{}) {
  return S::K(StateView<T>{q, p, z, t}, c);
}

template <Scene S, int i, class T, class C>
inline T K_q(const T* q, const T* p, T z, const C& c, T t = T{}) {
  return derivative<T>(S::K(StateView<T, Seed::q, i>{q, p, z, t}, c));
}

template <Scene S, int i, class T, class C>
inline T K_p(const T* q, const T* p, T z, const C& c, T t = T{}) {
  return derivative<T>(S::K(StateView<T, Seed::p, i>{q, p, z, t}, c));
}

template <Scene S, class T, class C>
inline T K_z(const T* q, const T* p, T z, const C& c, T t = T{}) {
  return derivative<T>(S::K(StateView<T, Seed::z>{q, p, z, t}, c));
}

// Calls f(std::integral_constant<int, i>{}) for i = 0 .. Dof−1.
template <int Dof, class F>
inline void for_each_dof(F&& f) {
  [&]<int... i>(std::integer_sequence<int, i...>) {
    (f(std::integral_constant<int, i>{}), ...);
  }(std::make_integer_sequence<int, Dof>{});
}

}  // namespace cs
