// One lane's state as an integrator sees it (T = double; the tiled kernel, engine/lane_tile.hpp,
// runs the same step over its lanes in a vectorised loop). The kernel keeps it in registers for
// a block of steps.
#pragma once

#include "numerics/lane_math.hpp"
#include "numerics/lane_math_dual.hpp"  // the same step on dual numbers
#include "physics/partials.hpp"

namespace cs {

template <int Dof, class T = double>
struct LaneState {
  T q[Dof];
  T p[Dof];
  T z;        // integrated only when the scene or a measure needs it
  T mu;       // ln λ, integrated only when a measure needs it: λ itself overflows near
              // t = 7100 for γ = 0.1, and p's update needs only ratios of λ
  // λ / e^mu = (lambda_numerator / lambda_denominator)·2^(512·lambda_folds): the hybrid
  // leap-frog with a state-dependent K_z multiplies its λ factors a and b up here (λ' = λ·a/b)
  // instead of taking two logs, or dividing, every step; 1, 1 and 0 in every other case.
  // ln λ: log_lambda.
  T lambda_numerator = T{} + 1.0;  // T{} + 1.0 also for a dual: value 1, derivative 0
  T lambda_denominator = T{} + 1.0;
  T lambda_folds = T{};
  T kq[Dof];  // K_q at the current state, reused by the next step where K_q ignores p
  T broken;   // > 0 once a λ factor 1 ± (h/2)K_z reached ≤ 0 (state-dependent K_z only)
  T t;        // the time of this state, t_start + n·h, set by the kernel before each step;
              // read only by time-dependent scenes
};

// Moves 2^512 out of a product of λ factors when it leaves [2^-511, 2^512): exact and
// branch-free; returns the power of 2^512 moved out (1, −1 or 0). The kernel folds its tile at
// least every 64 steps (engine/lane_tile.hpp), so the products never overflow: 64 steps would
// need factors of 2^8 each, h·K_z ≈ ±2, where the leap-frog has long broken down.
[[gnu::always_inline]] inline double fold_power_of_two(double& product) {
  const bool high = product >= 0x1p512, low = product < 0x1p-511;
  product = product * lane_math::select(high, 0x1p-512, lane_math::select(low, 0x1p512, 1.0));
  return lane_math::select(high, 1.0, lane_math::select(low, -1.0, 0.0));
}

// ln λ of a lane. Scaling by 2^±512 commutes exactly with a product's later roundings, so each
// product brought to canonical form — in [2^-511, 2^512) — is the same however often and
// whenever the kernel folded: ln λ has the same bits wherever the lane ran. Where K_z is
// constant the products stay 1 and mu is ln λ itself (no `+ log 1`, which turns −0 into +0).
// A scene may answer itself (engine/proxy_scene.hpp: a step kernel's).
template <Scene S, class T>
inline T log_lambda(const LaneState<S::dof, T>& x) {
  if constexpr (requires { S::log_lambda(x); }) {
    return S::log_lambda(x);
  } else if constexpr (S::kz_constant) {
    return x.mu;
  } else {
    constexpr double fold_log = 512 * 0x1.62e42fefa39efp-1;  // 512·ln 2 (an exact product)
    double folds = x.lambda_folds, numerator = x.lambda_numerator;
    double denominator = x.lambda_denominator;
    // A broken-down lane's product may be ≤ 0, inf or NaN: no canonical form, and no ln λ.
    auto canonical = [](double& product) {
      double moved = 0.0;
      while (product > 0.0 && product < INFINITY && (product >= 0x1p512 || product < 0x1p-511))
        moved += fold_power_of_two(product);
      return moved;
    };
    folds = folds + canonical(numerator) - canonical(denominator);
    return x.mu + (folds * fold_log + (lane_math::log(numerator) - lane_math::log(denominator)));
  }
}

// K_q at the lane's current state into its force cache: what the leap-frogs need before their
// first step (afterwards each step leaves K_q^{n+1} there for the next).
template <Scene S, class T, class C>
inline void cache_forces(LaneState<S::dof, T>& x, const C& c) {
  for_each_dof<S::dof>([&](auto i) { x.kq[i] = K_q<S, i>(x.q, x.p, x.z, c, x.t); });
}

// dz/dt = K − Σ p_i K_{p_i}, each product fused into the sum (lane_math::mul_add).
template <Scene S, class T, class C>
inline T z_rate(const T* q, const T* p, T z, const C& c, T t) {
  T r = K<S>(q, p, z, c, t);
  for_each_dof<S::dof>(
      [&](auto i) { r = lane_math::mul_add(-p[i], K_p<S, i>(q, p, z, c, t), r); });
  return r;
}

// Which optional state a kernel instantiation integrates.
struct Carry {
  bool z;
  bool mu;
  bool tangent = false;  // the lyapunov measure's tangent vector (engine/measures/): kernels
                         // built at run time only, so the built-in dispatch never has it
};

}  // namespace cs
