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
    using P = Point<D, T>;
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

 private:
  // A point of the extended state, or a rate of change of one.
  template <int D, class T>
  struct Point {
    T q[D], p[D], z, mu;
    Point() = default;
    explicit Point(const LaneState<D, T>& x) : z(x.z), mu(x.mu) {
      for (int i = 0; i < D; ++i) q[i] = x.q[i], p[i] = x.p[i];
    }
  };

  // y + a·r, fused
  template <bool with_z, bool with_mu, int D, class T>
  [[gnu::always_inline]] static Point<D, T> axpy(const Point<D, T>& y, T a, const Point<D, T>& r) {
    using lane_math::mul_add;
    Point<D, T> out;
    for (int i = 0; i < D; ++i) {
      out.q[i] = mul_add(a, r.q[i], y.q[i]);
      out.p[i] = mul_add(a, r.p[i], y.p[i]);
    }
    out.z = with_z ? mul_add(a, r.z, y.z) : y.z;
    out.mu = with_mu ? mul_add(a, r.mu, y.mu) : y.mu;
    return out;
  }

  template <Scene S, bool with_z, bool with_mu, class T, class C>
  [[gnu::always_inline]] static Point<S::dof, T> rate(const Point<S::dof, T>& y,
                                                      const C& c, T t) {
    Point<S::dof, T> r;
    const T kz = K_z<S>(y.q, y.p, y.z, c, t);
    T z_rate{};
    if constexpr (with_z) z_rate = K<S>(y.q, y.p, y.z, c, t);
    for_each_dof<S::dof>([&](auto i) {
      T kp = K_p<S, i>(y.q, y.p, y.z, c, t);
      r.q[i] = kp;
      r.p[i] = lane_math::mul_add(y.p[i], kz, -K_q<S, i>(y.q, y.p, y.z, c, t));
      if constexpr (with_z) z_rate = lane_math::mul_add(-y.p[i], kp, z_rate);
    });
    r.z = z_rate;
    r.mu = -kz;
    return r;
  }
};

}  // namespace cs
