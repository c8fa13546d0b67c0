// The stop's end of a lane in the block runner (engine/block_runner.hpp; the condition itself:
// engine/measures/observables.hpp): a lane flagged during a chunk is stepped again from the
// chunk's snapshot to the first step where the condition holds (an adaptive lane is held where
// it first held, located on its step's dense output by dense_step, which also takes the
// samples inside that step), and finished there, its exit as its basin's outcome. Member
// definitions of BlockRunner, included at the end of its header.
#pragma once

#include "engine/block_runner.hpp"

namespace cs {

// Lane i of tile t took a step that reached its next sample time (engine/dense_samples.hpp)
// or a window's end of its tangent (LyapunovLanes::in_step).
// A lane its stroboscopic map settled is looked at after this chunk (the early stop).
// A lane whose stop's condition holds at the step's end stops where it first held: its
// samples up to there, then it is held (no more attempts: its time set to t_end) until the
// runner looks at it (stop_lane).
template <Scene S, class Method, Carry carry, bool Uniform, class Formulas, MapperChoice Mappers,
          bool DenseOutput>
template <class Dense>
void BlockRunner<S, Method, carry, Uniform, Formulas, Mappers, DenseOutput>::dense_step(
    Tile& t, int i, const Dense& dense) {
  Book& b = (&t == &main_ ? main_book_ : fin_book_)[i];
  const bool settled = b.basin.settled;
  LaneState<D> end = t.lane(i);
  end.t = t.ad.t[i];
  const Params c = t.params(i);
  bool stopped = false;
  if constexpr (Formulas::stop) {
    if (formulas_.stops_now(t, i)) {
      LaneState<D> x;
      end.t = formulas_.locate_stop(dense, end.t, end, c, x);
      end = x;
      stopped = true;
      if constexpr (carry.tangent) lyapunov_.at_stop(&t == &main_, i, end.t);
    }
  }
  lyapunov_.in_step(&t == &main_, i, end.t);  // ln‖v‖ at the window's ends in the step
  dense_samples_.in_step(b, end, end.t, c, dense, sample_at(slot(t, i)), sync_at(),
                         strobe_at(slot(t, i)), window_at(slot(t, i)));
  t.ad.next_sample[i] = std::min(dense_samples_.next(b), lyapunov_.next_mark(slot(t, i)));
  if (b.basin.settled && !settled && &t == &main_) countdown_[i] = 0;
  if (stopped) {
    formulas_.hold_stop(slot(t, i), end);
    t.ad.t[i] = plan_.spec.t_end;
    t.ad.next_sample[i] = INFINITY;
  }
}

// Lane i of tile t (in `lane_slot`), flagged in its last advance of `steps` steps from b.n:
// stepped again to the stop, and finished there.
template <Scene S, class Method, Carry carry, bool Uniform, class Formulas, MapperChoice Mappers,
          bool DenseOutput>
void BlockRunner<S, Method, carry, Uniform, Formulas, Mappers, DenseOutput>::stop_lane(
    int lane_slot, const Tile& t, int i, Book& b, int steps) {
  const Params c = t.params(i);
  const Coef k = t.coef(i);
  LaneState<D> x;
  if constexpr (kAdaptive) {  // held where the condition first held (dense_step)
    x = formulas_.held_stop(lane_slot);
    LaneStatus status = LaneStatus::ok;
    if (lane_failed<S>(x, status)) return finish(lane_slot, b, x, c, status);
    return finish_stopped(lane_slot, b, x, c);
  } else if constexpr (carry.tangent) {
    // The state and its tangent stepped again together (lyapunov_lanes.hpp).
    b.n = formulas_.rerun(lane_slot, c, steps, x,
                          [&](std::int64_t base) { lyapunov_.rerun_begin(lane_slot, base); },
                          [&](LaneState<D>& y, std::int64_t n, int s) {
                            lyapunov_.rerun_step(lane_slot, y, n, s, steps, c, k);
                          });
    lyapunov_.rerun_end(lane_slot);
  } else {
    b.n = formulas_.rerun(lane_slot, c, steps, x, [](std::int64_t) {},
                          [&](LaneState<D>& y, std::int64_t, int) {
                            Method::template step<S, carry>(y, c, k);
                          });
  }
  x.t = clock_.at(b.n);
  LaneStatus status = LaneStatus::ok;
  if (lane_failed<S>(x, status)) return finish(lane_slot, b, x, c, status);
  finish_stopped(lane_slot, b, x, c);
}

// A healthy lane that stopped at step b.n in state x: its sample there, if one is due, and
// its exit as the basin's outcome — unless it settled first (with basin.early_stop = false it
// ran on after settling): a lane's outcome is the first decided.
template <Scene S, class Method, Carry carry, bool Uniform, class Formulas, MapperChoice Mappers,
          bool DenseOutput>
void BlockRunner<S, Method, carry, Uniform, Formulas, Mappers, DenseOutput>::finish_stopped(
    int lane_slot, Book& b, const LaneState<D>& x, const Params& c) {
  // An adaptive lane took its samples up to the stop from its step (dense_step); its time is
  // its own.
  const double time = kAdaptive ? x.t : clock_.at(b.n);
  if (plan_.samples > 0 && !kAdaptive) {
    const auto every = plan_.spec.measures.trajectory->every;
    if (b.n % every == 0 && b.n / every >= b.samples_recorded) {
      writer_.record_sample(b, b.n / every, x, c);
      formulas_.record_sample(lane_slot, b.point, b.n / every, b.n, x, c);
      b.samples_recorded = b.n / every + 1;
    }
  }
  const int exit = formulas_.exit_of(x, time, c);
  if (plan_.map.basin >= 0 && !b.basin.settled) {
    if (exit > 0) {
      b.basin.settled = true;
      b.basin.period = kExitPeriod;
      b.basin.point[0] = exit;
      b.basin.settle_time = time;
    }
  }
  finish(lane_slot, b, x, c, LaneStatus::ok, true, exit);
}

}  // namespace cs
