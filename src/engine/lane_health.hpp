// Whether a lane can start, and whether it has failed: the block runner's checks, shared with an
// adaptive lane's samples (dense_samples.hpp).
#pragma once

#include <cmath>

#include "engine/lane_status.hpp"
#include "numerics/lane_state.hpp"
#include "physics/partials.hpp"

namespace cs {

// The initial state and K, K_q, K_p, K_z there are finite (Lane–Emden's (2/t)·z at t = 0,
// log(q) at q < 0 are not).
// A scene may answer itself (engine/proxy_scene.hpp: a step kernel's).
template <Scene S>
bool defined_at(const LaneState<S::dof>& x, const ParamsOf<S, double>& c) {
  if constexpr (requires { S::defined_at(x, c); }) {
    return S::defined_at(x, c);
  } else {
    bool finite = std::isfinite(x.z) && std::isfinite(x.mu) &&
                  std::isfinite(K<S>(x.q, x.p, x.z, c, x.t)) &&
                  std::isfinite(K_z<S>(x.q, x.p, x.z, c, x.t));
    for_each_dof<S::dof>([&](auto i) {
      finite = finite && std::isfinite(x.q[i]) && std::isfinite(x.p[i]) &&
               std::isfinite(K_q<S, i>(x.q, x.p, x.z, c, x.t)) &&
               std::isfinite(K_p<S, i>(x.q, x.p, x.z, c, x.t));
    });
    return finite;
  }
}

// Broken down (the method's step failed) or diverged (beyond the scene's bound, not finite).
template <Scene S>
bool lane_failed(const LaneState<S::dof>& x, LaneStatus& status) {
  if (x.broken > 0.0) status = LaneStatus::breakdown;
  else if (S::diverged(x.q, x.p)) status = LaneStatus::diverged;
  return status != LaneStatus::ok;
}

}  // namespace cs
