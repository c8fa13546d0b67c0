// An adaptive method's samples (dop853): its lanes step to times of their own, so a trajectory
// sample (every `every`·h in time), a sync sample (at a fixed-step run's look times) or a sample
// of the stroboscopic map (at t_start + k·period, until the lane settles) or of an
// observe_window without trajectory (at every nominal step t_start + n·h in it) falls inside a
// step and is taken from the step's continuous extension (numerics/dop853_dense.hpp) when the
// lane's accepted step reaches it (engine/lane_tile.hpp's advance_adaptive calls the
// block runner, which calls in_step). A lane's samples come from its own steps alone: the same
// bits on any rank, thread or slot.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/lane_health.hpp"
#include "engine/lane_writer.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "engine/run_plan.hpp"

namespace cs {

template <Scene S>
class DenseSamples {
  static constexpr int D = S::dof;
  using Book = LaneBook<D>;
  using Params = ParamsOf<S, double>;

 public:
  explicit DenseSamples(const RunPlan& plan, LaneClock clock)
      : plan_(plan), clock_(clock), strobe_(plan.attractors.dense_strobe && plan.map.basin >= 0) {
    if (strobe_) strobe_clock_ = {plan.spec.t_start, *plan.spec.measures.basin->period};
    // The window's steps up to t_end (the nominal steps may round a hair beyond it).
    if (plan.observe.window_every_step) {
      window_last_ = plan.observe.window_last;
      const double slack = 1e-12 * (plan.spec.t_end - plan.spec.t_start);
      while (window_last_ > 0 && clock.at(window_last_) > plan.spec.t_end + slack) --window_last_;
    }
  }

  // Whether the run has samples of any kind (else its lanes never build a dense output): the
  // rule a kernel's DenseOutput is chosen by, in one place (run_plan.hpp).
  bool any() const { return samples_inside_steps(plan_); }

  // The time of the lane's next sample of any kind, +∞ when it has them all.
  double next(const Book& b) const {
    return std::min({next_sample_time(b), next_sync_time(b), next_strobe_time(b),
                     next_window_time(b)});
  }

  // The lane's accepted step ended at t_lane in state `end`: every sample up to t_lane, in time
  // order, from the step's continuous extension (the step's end from the state itself).
  // traj(b, k, x, c) records trajectory sample k; sync(b, n, x, c) takes sync's sample at step
  // n of the nominal clock; strobe(b, k, x, c) the stroboscopic map's sample k; window(b, n, x,
  // c) the window's sample at nominal step n.
  template <class Dense, class Traj, class Sync, class Strobe, class Window>
  void in_step(Book& b, const LaneState<D>& end, double t_lane, const Params& c,
               const Dense& dense, Traj&& traj, Sync&& sync, Strobe&& strobe, Window&& window) {
    for (double te = next(b); te <= t_lane; te = next(b)) {
      LaneState<D> x = end;
      if (te != t_lane) {
        const auto y = dense.at_time(te);
        for (int d = 0; d < D; ++d) x.q[d] = y.q[d], x.p[d] = y.p[d];
        x.z = y.z, x.mu = y.mu;
      }
      x.t = te;
      sample_at(b, x, c, te, traj, sync, strobe, window);
    }
  }

  // A lane at t_end: the samples whose time rounds a hair beyond it (RunPlan::samples, the
  // sync window's end rounded to a step) take its final state.
  template <class Traj, class Sync, class Strobe, class Window>
  void at_end(Book& b, const LaneState<D>& x, const Params& c, Traj&& traj, Sync&& sync,
              Strobe&& strobe, Window&& window) {
    for (double te = next(b); te < INFINITY; te = next(b))
      sample_at(b, x, c, te, traj, sync, strobe, window);
  }

  // A lane at t_start: the stroboscopic map's sample 0 (the other kinds take theirs from the
  // runner's look at load, the window's step 0 from FormulaTracker::load).
  template <class Strobe>
  void at_start(Book& b, const LaneState<D>& x, const Params& c, Strobe&& strobe) {
    b.window_n = std::max<std::int64_t>(plan_.observe.window_first, 1);
    if (next_strobe_time(b) != strobe_clock_.at(0)) return;
    strobe(b, b.strobe_k, x, c);
    ++b.strobe_k;
  }

 private:
  double next_sample_time(const Book& b) const {
    return b.samples_recorded < plan_.samples
               ? plan_.sample_times[static_cast<std::size_t>(b.samples_recorded)]
               : INFINITY;
  }
  // Steps sync_first_step, + chunk, … sync_last_step of the nominal clock, as a fixed-step
  // lane's looks.
  double next_sync_time(const Book& b) const {
    return plan_.map.sync_r >= 0 && b.sync_n <= plan_.sync_last_step ? clock_.at(b.sync_n)
                                                                      : INFINITY;
  }
  double next_window_time(const Book& b) const {
    return b.window_n <= window_last_ ? clock_.at(b.window_n) : INFINITY;
  }
  // Samples 0 … strobe_last of the stroboscopic map, until the lane settles.
  double next_strobe_time(const Book& b) const {
    return strobe_ && !b.basin.settled && b.strobe_k <= plan_.attractors.strobe_last
               ? strobe_clock_.at(b.strobe_k)
               : INFINITY;
  }

  // The samples due at time te, from the lane's state x there. A state that has failed
  // (beyond the scene's bound, not finite) ends the lane's sampling: its trajectory is NaN from
  // there (a sample not finite: the lane's status says so unless it fails anyway) and its sync
  // has no result, as a fixed-step lane's after it fails.
  template <class Traj, class Sync, class Strobe, class Window>
  void sample_at(Book& b, const LaneState<D>& x, const Params& c, double te, Traj& traj,
                 Sync& sync, Strobe& strobe, Window& window) {
    if (LaneStatus status = LaneStatus::ok; lane_failed<S>(x, status)) {
      LaneState<D> none = x;
      for (int d = 0; d < D; ++d) none.q[d] = none.p[d] = NAN;
      for (; b.samples_recorded < plan_.samples; ++b.samples_recorded)
        traj(b, b.samples_recorded, none, c);
      b.sync = SyncTracker{};
      b.sync_n = plan_.sync_last_step + 1;
      b.strobe_k = plan_.attractors.strobe_last + 1;  // its map ends undecided, as it fails
      b.window_n = window_last_ + 1;  // its statistics are NaN (its status)
      return;
    }
    if (next_sample_time(b) == te) {
      traj(b, b.samples_recorded, x, c);
      ++b.samples_recorded;
    }
    if (next_sync_time(b) == te) {
      sync(b, b.sync_n, x, c);
      b.sync_n += plan_.chunk;
    }
    if (next_strobe_time(b) == te) {
      strobe(b, b.strobe_k, x, c);
      ++b.strobe_k;
    }
    if (next_window_time(b) == te) {
      window(b, b.window_n, x, c);
      ++b.window_n;
    }
  }

  const RunPlan& plan_;
  LaneClock clock_;
  bool strobe_;
  LaneClock strobe_clock_{};  // sample k of the stroboscopic map at t_start + k·period
  std::int64_t window_last_ = -1;  // observe_window without trajectory: its last step (−1: none)
};

}  // namespace cs
