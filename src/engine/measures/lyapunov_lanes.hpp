// The lyapunov measure's part of the block runner: the tangents of the main and finisher tiles,
// seeded when a lane is loaded, moved with it, and turned into the `lyapunov` column when it
// finishes (tangent_lyapunov.hpp). Without Carry::tangent every call is empty and vanishes.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/lane_writer.hpp"
#include "engine/measures/tangent_tile.hpp"
#include "engine/run_plan.hpp"

namespace cs {

template <Scene S, class Method, Carry carry, int W>
class LyapunovLanes {
 public:
  LyapunovLanes(const RunPlan&, BlockResults&) {}
  void seed(int, const LaneState<S::dof>&, const ParamsOf<S, double>&) {}
  void clear(bool, int) {}
  void move(int, int) {}
  void finish(int, LaneBook<S::dof>&, LaneStatus) {}
};

template <Scene S, class Method, Carry carry, int W>
requires(carry.tangent) class LyapunovLanes<S, Method, carry, W> {
  static constexpr int D = S::dof;
  using Tile = LaneTile<S, Method, W>;

 public:
  LyapunovLanes(const RunPlan& plan, BlockResults& out) : plan_(plan), out_(out) {}

  // Main slot i now holds a fresh lane at x (its force cache set by Method::start).
  void seed(int i, const LaneState<D>& x, const ParamsOf<S, double>& c) {
    main_.set_lane(i, seeded_tangent<S, Method>(x, c, plan_.lyapunov_seed));
  }
  void clear(bool main, int i) { (main ? main_ : fin_).set_lane(i, LaneTangent<D>{}); }
  void move(int i, int j) { fin_.set_lane(j, main_.lane(i)); }

  template <bool Uniform>
  void advance(Tile& t, bool main, int steps, const ParamsOf<S, double>& uniform,
               const typename Method::template Coef<double>& uniform_coef, double t_start,
               double h) {
    advance_with_tangent<S, Method, carry, Uniform>(t, main ? main_ : fin_, steps, uniform,
                                                    uniform_coef, t_start, h);
  }

  // Slot `lane_slot` (main 0 … W−1, finisher W …) finishes after b.n steps. NaN where the lane
  // failed or never stepped; a healthy lane whose exponent is not finite is flagged through its
  // book (LaneWriter then writes non_finite_output).
  void finish(int lane_slot, LaneBook<D>& b, LaneStatus status) {
    double value = std::numeric_limits<double>::quiet_NaN();
    if (status == LaneStatus::ok && b.n > 0) {
      const LaneTangent<D> w = lane_slot < W ? main_.lane(lane_slot) : fin_.lane(lane_slot - W);
      value = lyapunov_value<D, tangent_has_z<S>()>(w.v, w.folds, plan_.lyapunov_log_norm0, b.n,
                                                    plan_.spec.h);
      if (!std::isfinite(value)) b.non_finite = true;
    }
    out_.columns[static_cast<std::size_t>(plan_.map.lyapunov)]
                [static_cast<std::size_t>(b.point - out_.range.begin)] = value;
  }

 private:
  const RunPlan& plan_;
  BlockResults& out_;
  TangentTile<S, W> main_{}, fin_{};
};

}  // namespace cs
