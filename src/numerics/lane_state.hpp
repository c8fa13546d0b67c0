// One lane's state as an integrator sees it (T = double; the tiled kernel, engine/lane_tile.hpp,
// runs the same step over its lanes in a vectorised loop). The kernel keeps it in registers for
// a block of steps.
#pragma once

#include "physics/partials.hpp"

namespace cs {

template <int Dof, class T = double>
struct LaneState {
  T q[Dof];
  T p[Dof];
  T z;        // integrated only when the scene or a measure needs it
  T mu;       // ln λ, integrated only when a measure needs it: λ itself overflows near
              // t = 7100 for γ = 0.1, and p's update needs only ratios of λ
  T kq[Dof];  // K_q at the current state, reused by the next step where K_q ignores p
  T broken;   // > 0 once a λ factor 1 ± (h/2)K_z reached ≤ 0 (state-dependent K_z only)
  T t;        // the time of this state, t_start + n·h, set by the kernel before each step;
              // read only by time-dependent scenes
};

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
