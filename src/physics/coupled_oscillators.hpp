// Scene D of the paper: two oscillators coupled by g q₁²q₂², damped through −γz:
// K = Σ (pᵢ² + ωᵢ²qᵢ²)/2 + g q₁²q₂² − γz. The paper gives ω₁² and ω₂², so those are the
// parameters (omega1_sq, omega2_sq). For g < 0 the potential is unbounded below and lanes escape.
#pragma once

#include <cmath>

#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

struct CoupledOscillators {
  static constexpr int dof = 2;
  static constexpr bool z_feeds_back = false;
  static constexpr bool kz_constant = true;
  static constexpr ZPart z_part = ZPart::linear;  // K = Σp²/2 + V(q) − γz

  template <class T>
  struct Params {
    T omega1_sq, omega2_sq, g, gamma;
  };
  template <class T>
  static Params<T> params_from(const T* v) { return {v[0], v[1], v[2], v[3]}; }

  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    auto q1q1 = square(q<0>(x)), q2q2 = square(q<1>(x));
    return half_square(p<0>(x)) + half_square(p<1>(x)) + 0.5 * (c.omega1_sq * q1q1) +
           0.5 * (c.omega2_sq * q2q2) + c.g * (q1q1 * q2q2) - c.gamma * z(x);
  }

  // The oscillators' own frequencies ω_i = √(ω_i²): the sync measure's default.
  static void natural_frequencies(const Params<double>& c, double* omega) {
    omega[0] = std::sqrt(c.omega1_sq), omega[1] = std::sqrt(c.omega2_sq);
  }

  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }
};

}  // namespace cs
