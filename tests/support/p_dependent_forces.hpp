#pragma once
// A scene for tests only, whose K_q and K_z depend on p: none of the paper's scenes does, so the
// integrators' implicit handling of such forces (hybrid_leapfrog.hpp, symmetric_leapfrog.hpp)
// needs one to be exercised. K_p depends on z, so z feeds back.
#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"

namespace cs::test {

//   K = p²/2 + q²/2 + ε q²p²/2 − γ z (1 + δ p²/2)
struct PDependentForces {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = true;
  static constexpr bool kz_constant = false;
  static constexpr bool p_in_forces = true;
  template <class T>
  struct Params {
    T eps, gamma, delta;
  };
  template <class T>
  static Params<T> params_from(const T* v) {
    return {v[0], v[1], v[2]};
  }
  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    const auto pp = p<0>(x) * p<0>(x), qq = q<0>(x) * q<0>(x);
    return 0.5 * pp + 0.5 * qq + (0.5 * c.eps) * (qq * pp) -
           c.gamma * z(x) * (1.0 + 0.5 * c.delta * pp);
  }
  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }
};

}  // namespace cs::test
