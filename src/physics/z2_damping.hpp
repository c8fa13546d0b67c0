// Scene B of the paper: K = (p² + ω²q²)/2 − γz², damping whose rate 2γz follows the state.
#pragma once

#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

struct Z2Damping {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = true;
  static constexpr bool kz_constant = false;
  static constexpr ZPart z_part = ZPart::quadratic;  // K = Σp²/2 + V(q) − γz²

  template <class T>
  struct Params {
    T omega, gamma;
  };
  template <class T>
  static Params<T> params_from(const T* v) { return {v[0], v[1]}; }

  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    return half_square(p<0>(x)) + (c.omega * c.omega) * half_square(q<0>(x)) -
           c.gamma * square(z(x));
  }

  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }
};

}  // namespace cs
