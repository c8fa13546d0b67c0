// The hybrid leap-frog of Sogo & Ohnishi (paper, sec. 3.1), exactly in the published sequential
// form, with the appended half-step predictors for z and q, and ln λ carried instead of λ:
//
//   λ^{n+½} = λ^n (1 − h/2 K_z^n)                          a = 1 − h/2 K_z^n
//   p^{n+½} = (λ^n/λ^{n+½}) (p^n − h/2 K_q^n)               λ^n/λ^{n+½} = 1/a
//   z^{n+½} = z^n + h/2 (K − pK_p)^n,  q^{n+½} = q^n + h/2 K_p^n     (predictors)
//   z^{n+1} = z^n + h (K − pK_p)^{n+½},  q^{n+1} = q^n + h K_p^{n+½}
//   λ^{n+1} = λ^{n+½} / (1 + h/2 K_z^{n+1})                  b = 1 + h/2 K_z^{n+1}
//   p^{n+1} = (λ^{n+½}/λ^{n+1}) p^{n+½} − h/2 K_q^{n+1}      λ^{n+½}/λ^{n+1} = b
//
// (·)^{n+½} is evaluated at (q^{n+½}, p^{n+½}, z^{n+½}). The paper leaves open which p enters
// K_z^{n+1} and K_q^{n+1} when they depend on p. We take p^{n+1} itself, so the last line is
// implicit in p, solved by fixed-point passes from p^{n+½} (kEndForcePasses in all). The explicit
// choice, p^{n+½}, was measured first order (observed 0.93 and 0.90 on a test scene): it leaves an
// error h/2·K_qp·(p^{n+1} − p^{n+½}) = O(h²) per step. Each pass gains a factor h/2·|K_qp −
// p^{n+½}·K_zp| = O(h); the explicit value plus four more passes leave O(h⁵) per step, far below
// the method's O(h³). Where K_q and K_z do not depend on p (every scene of the paper) the step is
// explicit, and K_q^{n+1} equals the next step's K_q^n bit for bit, so it is kept: one force
// evaluation per step.
//
// A time-dependent K is evaluated at t_n on the first lines, at t_{n+½} = t_n + h/2 at the
// predicted midpoint and at t_{n+1} = t_n + h for the end forces: each line then approximates
// the same integral it does for an autonomous K, and the order stays 2 (tests/test_methods.cpp,
// forced oscillator). The kept K_q^{n+1} was taken at t_n + h, which may differ from the next
// step's t_start + (n+1)·h in the last bit: a deterministic O(ulp) difference in time.
#pragma once

#include <cmath>
#include <type_traits>

#include "numerics/lane_math.hpp"
#include "numerics/lane_state.hpp"
#include "numerics/method_description.hpp"
#include "physics/partials.hpp"

namespace cs {

struct HybridLeapfrog {
  static constexpr MethodDescription description{
      .name = "hybrid_leapfrog",
      .catalog_position = 1,
      .order = 2,
      .properties = "Sogo & Ohnishi's hybrid leap-frog (paper, sec. 3.1), explicit; (q, lambda p) "
                    "conformally symplectic; H = lambda K drifts linearly",
      .force_evaluations_per_step = 1,
      .documentation = "The published method, line for line: choose it to reproduce the paper. "
                       "For other second-order work contact_splitting2 is as accurate, cheaper "
                       "per step and keeps H bounded.",
  };

  static constexpr int kEndForcePasses = 5;  // scenes whose K_q or K_z depend on p only

  // Per-lane constants, computed once when a lane is loaded. inv_a, b and dmu = ln a − ln b are
  // used only where K_z is constant; otherwise the factors are computed every step.
  template <class T>
  struct Coef {
    T h, half_h, inv_a, b, dmu;
  };

  template <Scene S>
  static Coef<double> coefficients(double h, const ParamsOf<S, double>& c,
                                   const LaneState<S::dof>& x) {
    Coef<double> k{h, 0.5 * h, 0.0, 0.0, 0.0};
    if constexpr (S::kz_constant) {
      double kz = K_z<S>(x.q, x.p, x.z, c, x.t);
      double a = 1.0 - k.half_h * kz, b = 1.0 + k.half_h * kz;
      k.inv_a = 1.0 / a;
      k.b = b;
      k.dmu = std::log(a) - std::log(b);
    }
    return k;
  }

  // A constant K_z that makes a λ factor non-positive breaks every step: known at load time.
  template <Scene S>
  static bool breaks_down(const Coef<double>& k) {
    return S::kz_constant && !(k.inv_a > 0.0 && k.b > 0.0);
  }

  // Called once when a lane is loaded: the first step needs K_q at the initial state.
  template <Scene S, class T, class C>
  static void start(LaneState<S::dof, T>& x, const C& c) {
    cache_forces<S>(x, c);
  }

  // Forced inline with everything it calls, as the other methods' steps: with a state-dependent
  // K_z (two lane_math::log a step) the step exceeds GCC's inlining limits, and a call inside
  // the kernel's lane loop stops it from vectorising (scene B ran 55x slower than A).
  //
  // P, the coefficients' number type, is T or double: the tangent step (T = Dual<double>) takes
  // them as plain doubles (plain_coefficients), which spares the products with their zero
  // derivative parts; the value parts are the same operations either way.
  static constexpr bool plain_coefficients = true;

  template <Scene S, Carry carry, class T, class C, class P>
  [[gnu::always_inline, gnu::flatten]] static void step(LaneState<S::dof, T>& x,
                                                        const C& c, const Coef<P>& k) {
    using lane_math::mul_add;  // x + h·f as one rounding (lane_math.hpp)
    constexpr int D = S::dof;
    constexpr bool with_z = carry.z || S::z_feeds_back;
    using Factor = std::conditional_t<S::kz_constant, P, T>;  // λ factors: per lane or per step
    const P hh = k.half_h;
    const T t0 = x.t, t_half = x.t + hh, t1 = x.t + k.h;

    if constexpr (p_in_forces<S>()) start<S>(x, c);

    Factor inv_a;
    T a{};
    if constexpr (S::kz_constant) {
      inv_a = k.inv_a;
    } else {
      a = mul_add(-hh, K_z<S>(x.q, x.p, x.z, c, t0), 1.0);
      inv_a = 1.0 / a;
    }

    T p_half[D], q_half[D];
    for (int i = 0; i < D; ++i) p_half[i] = inv_a * mul_add(-hh, x.kq[i], x.p[i]);
    T z_half = x.z;
    if constexpr (with_z) z_half = mul_add(hh, z_rate<S>(x.q, x.p, x.z, c, t0), x.z);
    for_each_dof<D>([&](auto i) {
      q_half[i] = mul_add(hh, K_p<S, i>(x.q, x.p, x.z, c, t0), x.q[i]);
    });

    if constexpr (with_z) x.z = mul_add(k.h, z_rate<S>(q_half, p_half, z_half, c, t_half), x.z);
    for_each_dof<D>([&](auto i) {
      x.q[i] = mul_add(k.h, K_p<S, i>(q_half, p_half, z_half, c, t_half), x.q[i]);
    });

    // End forces K_q^{n+1}, K_z^{n+1}, and p^{n+1} = b·p^{n+½} − h/2·K_q^{n+1}.
    Factor b{};  // state-dependent K_z: set by end_forces_at
    if constexpr (S::kz_constant) b = k.b;
    auto end_forces_at = [&](const T* p) {
      if constexpr (!S::kz_constant) b = mul_add(hh, K_z<S>(x.q, p, x.z, c, t1), 1.0);
      for_each_dof<D>([&](auto i) { x.kq[i] = K_q<S, i>(x.q, p, x.z, c, t1); });
      for (int i = 0; i < D; ++i) x.p[i] = mul_add(-hh, x.kq[i], b * p_half[i]);
    };
    end_forces_at(p_half);
    if constexpr (p_in_forces<S>()) {
      // Implicit in p^{n+1}: fixed-point passes from the explicit value; x.p is read (through
      // a copy) and rewritten each pass.
      for (int pass = 1; pass < kEndForcePasses; ++pass) {
        T p_iterate[D];
        for (int i = 0; i < D; ++i) p_iterate[i] = x.p[i];
        end_forces_at(p_iterate);
      }
    }
    if constexpr (S::kz_constant) {
      if constexpr (carry.mu) x.mu = x.mu + k.dmu;
    } else {
      // One test for both factors (a NaN factor is no breakdown: the lane diverges instead).
      x.broken += ((a < b ? a : b) <= 0.0);
      // λ^{n+1} = λ^n·a/b: a and b multiplied up, no log or division a step (scene B's cost).
      if constexpr (carry.mu) {
        x.lambda_numerator = x.lambda_numerator * a;  // folded by the kernel (lane_state.hpp)
        x.lambda_denominator = x.lambda_denominator * b;
      }
    }
  }
};

}  // namespace cs
