// A grid point as a lane at the start of its run: its initial state (q.., p.., z, ln λ) and its
// parameters, from the grid (engine/grid.hpp), as the method starts it (Method::start).
#pragma once

#include <cmath>
#include <cstdint>

#include "engine/run_plan.hpp"
#include "numerics/lane_state.hpp"

namespace cs {

template <Scene S>
struct StartedLane {
  LaneState<S::dof> x;
  ParamsOf<S, double> c;
};

// Point `index` of the plan's grid (counted from the plan's first point) at t_start.
template <Scene S, class Method>
StartedLane<S> start_lane(const RunPlan& plan, std::int64_t index, double t_start) {
  constexpr int D = S::dof;
  double params[sizeof(ParamsOf<S, double>) / sizeof(double)], state[2 * D + 2];
  plan.grid.point(index, params, state);
  StartedLane<S> lane{};
  LaneState<D>& x = lane.x;
  for (int d = 0; d < D; ++d) x.q[d] = state[d], x.p[d] = state[D + d];
  x.z = state[2 * D];
  x.mu = std::log(state[2 * D + 1]);
  x.lambda_numerator = x.lambda_denominator = 1.0;
  x.lambda_folds = 0.0;
  x.broken = 0.0;
  x.t = t_start;
  lane.c = S::params_from(params);
  Method::template start<S>(x, lane.c);
  return lane;
}

}  // namespace cs
