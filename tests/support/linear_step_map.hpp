// On scene A (K = (p² + ω²q²)/2 − γz) every method's step maps (q, p) linearly, independently of
// z and λ: its matrix is read off by stepping the unit vectors.
#pragma once

#include <Eigen/Dense>

#include "numerics/lane_state.hpp"
#include "physics/damped_oscillator.hpp"

namespace cs::test {

template <class Method>
Eigen::Matrix2d one_step_matrix(double h, double omega, double gamma) {
  using S = DampedOscillator;
  const ParamsOf<S, double> c{omega, gamma};
  Eigen::Matrix2d m;
  for (int j = 0; j < 2; ++j) {
    LaneState<1> x{};
    x.q[0] = j == 0 ? 1.0 : 0.0;
    x.p[0] = j == 1 ? 1.0 : 0.0;
    Method::template start<S>(x, c);
    auto k = Method::template coefficients<S>(h, c, x);
    Method::template step<S, Carry{false, false}>(x, c, k);
    m(0, j) = x.q[0];
    m(1, j) = x.p[0];
  }
  return m;
}

inline double spectral_radius(const Eigen::Matrix2d& m) {
  return m.eigenvalues().cwiseAbs().maxCoeff();
}

}  // namespace cs::test
