// Scene C of the paper: K = p²/2 + U(q) − γz with U(q) = (q² − a²)²/2, the damped double well.
#pragma once

#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

struct DoubleWell {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = false;
  static constexpr bool kz_constant = true;
  static constexpr ZPart z_part = ZPart::linear;  // K = Σp²/2 + V(q) − γz

  template <class T>
  struct Params {
    T a, gamma;
  };
  template <class T>
  static Params<T> params_from(const T* v) { return {v[0], v[1]}; }

  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    return half_square(p<0>(x)) + half_square(square(q<0>(x)) - c.a * c.a) - c.gamma * z(x);
  }

  // Mechanical energy E = p²/2 + U(q); dE/dt = −γp², so it never increases for γ ≥ 0.
  static double energy(double q, double p, double a) {
    double well = q * q - a * a;
    return 0.5 * (p * p) + 0.5 * (well * well);
  }

  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }
};

}  // namespace cs
