// Two time-dependent scenes with closed-form solutions (shared/PHYSICS.md, re-derived), written
// by hand as a generated scene would be: they test every method's times without the run-time
// compiler.
//
// Forced damped oscillator K = p²/2 + ω²q²/2 − F q cos(Ωt) − γz: q'' + γq' + ω²q = F cos Ωt.
// The solution is the particular one A cos Ωt + B sin Ωt, with A = F(ω² − Ω²)/D, B = FγΩ/D,
// D = (ω² − Ω²)² + γ²Ω², plus the damped homogeneous flow of what is left at t₀; ln λ grows by
// γ(t − t₀) exactly. (λK is not conserved here: d(λK)/dt = λK_t.)
//
// Lane–Emden, n = 5: K = p²/2 + q⁶/6 − (2/t)z, i.e. θ'' + (2/t)θ' + θ⁵ = 0, whose solution with
// θ(0) = 1, θ'(0) = 0 is θ = (1 + t²/3)^(−1/2); λ = λ₀(t/t₀)². The damping 2/t depends on time
// only (K_z is state-free but not constant).
#pragma once

#include <cmath>

#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"
#include "exact_damped_oscillator.hpp"

namespace cs::test {

struct ForcedOscillator {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = false;
  static constexpr bool kz_constant = true;
  static constexpr bool time_dependent = true;
  static constexpr ZPart z_part = ZPart::linear;

  template <class T>
  struct Params {
    T omega, gamma, F, Omega;
  };
  template <class T>
  static Params<T> params_from(const T* v) { return {v[0], v[1], v[2], v[3]}; }

  template <class X, class T>
  static auto K(const X& x, const Params<T>& c) {
    return half_square(p<0>(x)) + (c.omega * c.omega) * half_square(q<0>(x)) -
           c.F * q<0>(x) * std::cos(c.Omega * t(x)) - c.gamma * z(x);
  }
  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }

  // q, p and ln λ at time t from (q0, p0, λ = 1) at t0.
  static ExactState exact(const Params<double>& c, double t0, double q0, double p0, double t) {
    const double w2 = c.omega * c.omega, W = c.Omega;
    const double D = (w2 - W * W) * (w2 - W * W) + c.gamma * c.gamma * W * W;
    const double A = c.F * (w2 - W * W) / D, B = c.F * c.gamma * W / D;
    auto particular_q = [&](double s) { return A * std::cos(W * s) + B * std::sin(W * s); };
    auto particular_p = [&](double s) { return W * (B * std::cos(W * s) - A * std::sin(W * s)); };
    ExactState h = exact_damped_oscillator(t - t0, c.omega, c.gamma, q0 - particular_q(t0),
                                           p0 - particular_p(t0), 0.0, 1.0);
    return {h.q + particular_q(t), h.p + particular_p(t), 0.0, c.gamma * (t - t0)};
  }
};

struct LaneEmden5 {
  static constexpr int dof = 1;
  static constexpr bool z_feeds_back = false;
  static constexpr bool kz_constant = false;
  static constexpr bool time_dependent = true;
  static constexpr ZPart z_part = ZPart::linear;

  template <class T>
  struct Params {
    T none;  // no parameters
  };
  template <class T>
  static Params<T> params_from(const T*) { return {T{}}; }

  template <class X, class T>
  static auto K(const X& x, const Params<T>&) {
    auto q2 = square(q<0>(x));
    return half_square(p<0>(x)) + (q2 * q2 * q2) * (1.0 / 6.0) - (2.0 / t(x)) * z(x);
  }
  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }

  static ExactState exact(double t, double t0) {
    const double s = 1.0 + t * t / 3.0;
    return {1.0 / std::sqrt(s), -(t / 3.0) / (s * std::sqrt(s)), 0.0, 2.0 * std::log(t / t0)};
  }
};

}  // namespace cs::test
