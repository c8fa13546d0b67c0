// One lane's state as an integrator sees it (T = double; the tiled kernel, engine/lane_tile.hpp,
// runs the same step over its lanes in a vectorised loop). The kernel keeps it in registers for
// a block of steps.
#pragma once

#include "numerics/lane_math.hpp"
#include "physics/partials.hpp"

namespace cs {

template <int Dof, class T = double>
struct LaneState {
  T q[Dof];
  T p[Dof];
  T z;        // integrated only when the scene or a measure needs it
  T mu;       // ln λ, integrated only when a measure needs it: λ itself overflows near
              // t = 7100 for γ = 0.1, and p's update needs only ratios of λ
  T lambda_factor = T(1);  // λ / e^mu: the hybrid leap-frog with a state-dependent K_z
                           // multiplies its λ factors a/b up here instead of taking two logs a
                           // step (fold_lambda_factor); 1 for every other case. ln λ: log_lambda
  T kq[Dof];  // K_q at the current state, reused by the next step where K_q ignores p
  T broken;   // > 0 once a λ factor 1 ± (h/2)K_z reached ≤ 0 (state-dependent K_z only)
  T t;        // the time of this state, t_start + n·h, set by the kernel before each step;
              // read only by time-dependent scenes
};

// ln λ of a lane. Where K_z is constant lambda_factor stays 1 and mu is ln λ itself (no
// `+ log 1`, which would turn a −0 into +0).
template <Scene S, class T>
inline T log_lambda(const LaneState<S::dof, T>& x) {
  if constexpr (S::kz_constant) return x.mu;
  else return x.mu + lane_math::log(x.lambda_factor);
}

// Keeps lambda_factor within 2^±512 by moving 2^512 into mu when it leaves: exact in the
// factor, one rounding in mu every 355 units of ln λ, branch-free so that the lane loop still
// vectorises. Only a step whose factor a/b exceeds 2^511 could overflow it (h·K_z ≈ ±2, where
// the leap-frog has long broken down).
[[gnu::always_inline]] inline void fold_lambda_factor(double& mu, double& lambda_factor) {
  constexpr double fold_log = 512 * 0x1.62e42fefa39efp-1;  // 512·ln 2 (exact product)
  const bool high = lambda_factor >= 0x1p512, low = lambda_factor < 0x1p-511;
  lambda_factor =
      lambda_factor * lane_math::select(high, 0x1p-512, lane_math::select(low, 0x1p512, 1.0));
  mu = mu + lane_math::select(high, fold_log, lane_math::select(low, -fold_log, 0.0));
}

// K_q at the lane's current state into its force cache: what the leap-frogs need before their
// first step (afterwards each step leaves K_q^{n+1} there for the next).
template <Scene S, class T>
inline void cache_forces(LaneState<S::dof, T>& x, const ParamsOf<S, T>& c) {
  for_each_dof<S::dof>([&](auto i) { x.kq[i] = K_q<S, i>(x.q, x.p, x.z, c, x.t); });
}

// Which optional state a kernel instantiation integrates.
struct Carry {
  bool z;
  bool mu;
};

}  // namespace cs
