// Classical fourth-order Runge–Kutta on the full contact vector field
//   q' = K_p,  p' = −K_q + p·K_z,  z' = K − Σ p_i K_{p_i},  (ln λ)' = −K_z
// with the partials derived from the scene's K. Works on any scene; accurate but not geometric:
// H = λK drifts linearly (−1.8e-5 over t = 10⁴ at h = 0.05 on scene A, γ = 0.01), and the
// stability limit on scene A (ω = 1, γ = 0.1) is h < 2.9098 (tests/test_stability.cpp).
//
// A time-dependent K is evaluated at the classical stage times t_n, t_n + h/2 (twice), t_n + h.
// z is integrated only when it feeds back or is asked for; ln λ never feeds back, and where K_z
// is constant its exact increment −h·K_z (which RK4 reproduces) is precomputed per lane.
#pragma once

#include "numerics/contact_field.hpp"
#include "numerics/lane_state.hpp"
#include "numerics/method_description.hpp"
#include "physics/partials.hpp"

namespace cs {

struct Rk4 {
  static constexpr MethodDescription description{
      .name = "rk4",
      .catalog_position = 6,
      .order = 4,
      .properties = "classical Runge-Kutta on the full contact vector field; any scene; not "
                    "geometric: H drifts slowly",
      .force_evaluations_per_step = 4,
      .documentation = "Cheapest per trajectory for moderate accuracy over short times (final "
                       "error 1e-2 to 1e-6), and for basin maps that must agree with a fine "
                       "reference to a few cells; its H drifts.",
  };

  template <class T>
  struct Coef {
    T h, half_h, sixth_h;
    T dmu;  // −h·K_z when K_z is constant
  };

  template <Scene S>
  static Coef<double> coefficients(double h, const ParamsOf<S, double>& c,
                                   const LaneState<S::dof>& x) {
    Coef<double> k{h, 0.5 * h, h / 6.0, 0.0};
    if constexpr (S::kz_constant) k.dmu = -h * K_z<S>(x.q, x.p, x.z, c, x.t);
    return k;
  }

  template <Scene S>
  static bool breaks_down(const Coef<double>&) {
    return false;
  }

  template <Scene S, class T, class C>
  static void start(LaneState<S::dof, T>&, const C&) {}

  // Forced inline, with everything it calls: the kernel's lane loop vectorises only if the whole
  // step is one straight block inside it (a step of this size exceeds GCC's inlining limits).
  template <Scene S, Carry carry, class T, class C>
  [[gnu::always_inline, gnu::flatten]] static void step(LaneState<S::dof, T>& x,
                                                        const C& c, const Coef<T>& k) {
    constexpr int D = S::dof;
    constexpr bool with_z = carry.z || S::z_feeds_back;
    constexpr bool with_mu = carry.mu && !S::kz_constant;
    using P = contact_field::Point<D, T>;
    using contact_field::axpy;
    using contact_field::rate;
    const P x0{x};
    const T t_half = x.t + k.half_h, t1 = x.t + k.h;
    const P k1 = rate<S, with_z, with_mu>(x0, c, x.t);
    const P k2 = rate<S, with_z, with_mu>(axpy<with_z, with_mu>(x0, k.half_h, k1), c, t_half);
    const P k3 = rate<S, with_z, with_mu>(axpy<with_z, with_mu>(x0, k.half_h, k2), c, t_half);
    const P k4 = rate<S, with_z, with_mu>(axpy<with_z, with_mu>(x0, k.h, k3), c, t1);
    // y + h/6·(r1 + 2r2 + 2r3 + r4)
    auto combine = [&](T y, T r1, T r2, T r3, T r4) {
      return lane_math::mul_add(k.sixth_h, lane_math::mul_add(2.0, r2 + r3, r1 + r4), y);
    };
    for (int i = 0; i < D; ++i) {
      x.q[i] = combine(x.q[i], k1.q[i], k2.q[i], k3.q[i], k4.q[i]);
      x.p[i] = combine(x.p[i], k1.p[i], k2.p[i], k3.p[i], k4.p[i]);
    }
    if constexpr (with_z) x.z = combine(x.z, k1.z, k2.z, k3.z, k4.z);
    if constexpr (with_mu)
      x.mu = combine(x.mu, k1.mu, k2.mu, k3.mu, k4.mu);
    else if constexpr (carry.mu)
      x.mu = x.mu + k.dmu;
  }

};

}  // namespace cs
