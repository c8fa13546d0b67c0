// Measures as formulas in the kernel ([measures] observe, observe_window, stop; docs/
// observables.md). `M` is the struct the run-time kernel is generated with
// (formula/measure_formulas.hpp, measures_source): observe(x, c, v), stops(x, c), exit(x, c),
// reading the state through q<i>(x), p<i>(x), z(x), t(x), lambda(x) of an ObservableView.
// Built-in kernels are compiled with NoMeasureFormulas, for which all of this is empty.
//
// The stop: the condition is evaluated after every step, vectorised over the tile (after_step:
// one flag per lane, ORed; the state is not frozen). A lane flagged during a chunk is looked at
// when the chunk ends: its state at the chunk's start (a snapshot taken before every chunk) is
// stepped again, in scalar code by the same step function, until the condition holds — the same
// bits as in the tile, so the stop is at the end of the first step where it held. Its slot is
// then free for the next lane: a stopped lane costs nothing after its stop but the rest of the
// chunk it stopped in.
//
// An adaptive method (dop853) has no common steps to step again: the condition is evaluated after
// each accepted step of each lane (advance_adaptive's watch), and where it holds the time it
// first held is located on the step's continuous extension (locate_stop, bisection); the lane
// is held there (hold_stop) until the runner looks at it.
//
// The window statistics: with a trajectory the samples are the trajectory's (looks); without
// one every step is a sample, accumulated in the same vectorised pass (after_step), and an
// adaptive lane's every nominal step t_start + n·h in the window (window_sample). A lane's sums
// run in the order of its steps: the same bits on any rank or thread.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "engine/lane_tile.hpp"
#include "engine/lane_writer.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "engine/measures/formula_steps.hpp"
#include "engine/measures/observable_view.hpp"
#include "engine/run_plan.hpp"
#include "engine/run_traits.hpp"
#include "numerics/lane_state.hpp"

namespace cs {

// Per-lane state of observe and stop, by slot (0 … W−1 main tile, W … 2W−1 finisher).
//
// Over a step kernel's proxy scene (M = ProxyFormulas, engine/proxy_scene.hpp) the formulas are
// the kernel's: their values one lane at a time through its table, and the every-step work inside
// its step loop (advance_in_kernel), which this tracker hands its FormulaSteps. The kernel
// carries what the run's formulas read; the runner's own carried state says nothing of it, so a
// proxy's snapshot and rerun keep the fields the kernel says it carries.
template <Scene S, class Method, Carry carry, bool Uniform, class M, int W>
class FormulaTracker {
  static constexpr int D = S::dof;
  static constexpr int K = M::observables > 0 ? M::observables : 1;
  // What the run has, at compile time or a step kernel's at run time (run_traits.hpp): over a
  // step kernel M's constants are the runner's room, and the fields the kernel's step writes
  // are what a stop's snapshot keeps for the rerun.
  using Formulas = FormulaTraits<M>;
  using Traits = SceneTraits<S, carry>;
  static constexpr bool kInKernel = Formulas::in_step_kernel;
  using Tile = LaneTile<S, Method, W>;
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;

 public:
  FormulaTracker(const RunPlan& plan, BlockResults& out, LaneClock clock, const Params& uniform)
      : plan_(plan), o_(plan.observe), out_(out), clock_(clock), uniform_(uniform) {
    a_.window_first = o_.window_first;
    a_.window_last = o_.window_last;
    for (int s = 0; s < 2 * W; ++s) clear(s);
  }

  // What a formula reads of a lane at time t (formula_steps.hpp).
  static ObservableView<D> view(const LaneState<D>& x, double t) {
    return formula_view<S, M>(x, t);
  }

  void clear(int slot) {
    a_.hit[slot] = 0;
    a_.count[slot] = 0.0;
    a_.nan[slot] = 0.0;
    for (int k = 0; k < Formulas::observables(); ++k)
      a_.sum[k][slot] = 0.0, a_.min[k][slot] = INFINITY, a_.max[k][slot] = -INFINITY;
  }

  void move(int from, int to) {
    a_.count[to] = a_.count[from];
    a_.nan[to] = a_.nan[from];
    for (int k = 0; k < Formulas::observables(); ++k)
      a_.sum[k][to] = a_.sum[k][from], a_.min[k][to] = a_.min[k][from],
      a_.max[k][to] = a_.max[k][from];
    a_.hit[to] = 0;
  }

  // A lane loaded at step 0: its first sample, and whether it stops there already.
  bool load(int slot, const LaneState<D>& x, const Params& c) {
    clear(slot);
    const ObservableView<D> v = view(x, clock_.at(0));
    if (o_.window_every_step && o_.window_first == 0) accumulate(slot, v, c);
    if constexpr (M::stop) return M::stops(v, c);
    return false;
  }

  // Whether the run's formulas have work after every step (the stop's condition, a window
  // without trajectory): before_advance reads the lanes' step counts only then.
  bool after_every_step() const { return Formulas::stop() || o_.window_every_step; }

  // Before a tile is advanced by `steps`: whether its steps need after_step (the stop's
  // condition; the window's samples when the chunk can reach the window), and if so the lanes'
  // step counts and, for the stop, a snapshot to step again from. Without it the step loop
  // runs as in a kernel without formulas.
  bool before_advance(const Tile& t, int which, const std::int64_t* steps_done, int steps) {
    const int b = which * W;
    bool window = false;
    if constexpr (M::observables > 0) {
      if (o_.window_every_step) {
        std::int64_t lo = steps_done[0], hi = steps_done[0];
        for (int i = 1; i < W; ++i) lo = std::min(lo, steps_done[i]), hi = std::max(hi, steps_done[i]);
        window = hi + steps >= o_.window_first && lo + 1 <= o_.window_last;
      }
    }
    a_.window_now = window;
    const bool stop = Formulas::stop();
    if (!stop && !window) return false;
    for (int i = 0; i < W; ++i) a_.base[b + i] = steps_done[i], a_.hit[b + i] = 0;
    if (!stop) return true;
    Snapshot& s = snapshot_[which];
    std::memcpy(s.q, t.q, sizeof s.q);
    std::memcpy(s.p, t.p, sizeof s.p);
    std::memcpy(s.kq, t.kq, sizeof s.kq);
    if (Traits::carries_z()) std::memcpy(s.z, t.z, sizeof s.z);
    if (Traits::carries_mu()) {
      std::memcpy(s.mu, t.mu, sizeof s.mu);
      std::memcpy(s.numerator, t.lambda_numerator, sizeof s.numerator);
      std::memcpy(s.denominator, t.lambda_denominator, sizeof s.denominator);
      std::memcpy(s.folds, t.lambda_folds, sizeof s.folds);
    }
    if (!Traits::kz_constant()) std::memcpy(s.broken, t.broken, sizeof s.broken);
    if (o_.window_every_step) {
      // Both tiles' slots of the run's observables (a step kernel's runner has room for more).
      const auto rows = static_cast<std::size_t>(Formulas::observables()) * sizeof s.sum[0];
      std::memcpy(s.sum, &a_.sum[0][0], rows);
      std::memcpy(s.min, &a_.min[0][0], rows);
      std::memcpy(s.max, &a_.max[0][0], rows);
      std::memcpy(s.count, a_.count, sizeof s.count);
      std::memcpy(s.nan, a_.nan, sizeof s.nan);
    }
    return true;
  }

  // After step s of an advance (the tile's lanes at step base + s + 1): the stop's flags and
  // the window's every-step samples, vectorised over the tile (formula_steps.hpp).
  void after_step(const Tile& t, int which, int s) {
    static_assert(!kInKernel, "a step kernel's formulas run after each step in its step loop");
    formula_after_step<S, carry, Uniform, M>(t, which, s, a_, clock_, uniform_);
  }

  // Over a proxy scene, after before_advance said the advance needs the every-step work: the
  // kernel's step loop with it (StepKernel::advance_watched).
  void advance_in_kernel(Tile& t, int which, int steps, const Params& uniform, const Coef& coef) {
    static_assert(kInKernel);
    M::advance_watched(&t, steps, uniform.v, coef.v, clock_.t_start, clock_.h, which, &a_);
  }

  // The main tile's lanes that stopped during the chunk need a look.
  void screen(LookInt* attention) const {
    if (Formulas::stop())
      for (int i = 0; i < W; ++i) attention[i] |= a_.hit[i];
  }

  bool hit(int slot) const {
    if constexpr (M::stop) return a_.hit[slot] != 0;
    return false;
  }

  // A lane flagged in the last advance of its tile: stepped again from the snapshot until the
  // condition holds. Returns the stop's step count, x its state there. begin(base) once, then
  // step(x, n, s) makes step s of the rerun from step count n (x.t set): the method's step, or
  // the step with the lyapunov measure's tangent (lyapunov_lanes.hpp).
  template <class Begin, class Step>
  std::int64_t rerun(int slot, const Params& c, int steps, LaneState<D>& x, Begin&& begin,
                     Step&& step_one) {
    const int which = slot / W, i = slot % W;
    const Snapshot& s = snapshot_[which];
    x = LaneState<D>{};
    for (int d = 0; d < D; ++d) x.q[d] = s.q[d][i], x.p[d] = s.p[d][i], x.kq[d] = s.kq[d][i];
    x.z = 0.0, x.mu = 0.0, x.broken = 0.0;
    if (Traits::carries_z()) x.z = s.z[i];
    if (Traits::carries_mu()) {
      x.mu = s.mu[i];
      x.lambda_numerator = s.numerator[i];
      x.lambda_denominator = s.denominator[i];
      x.lambda_folds = s.folds[i];
    }
    if (!Traits::kz_constant()) x.broken = s.broken[i];
    if (o_.window_every_step) {
      a_.count[slot] = s.count[slot];
      a_.nan[slot] = s.nan[slot];
      for (int k = 0; k < Formulas::observables(); ++k)
        a_.sum[k][slot] = s.sum[k][slot], a_.min[k][slot] = s.min[k][slot],
        a_.max[k][slot] = s.max[k][slot];
    }
    std::int64_t n = a_.base[slot];
    begin(n);
    for (int step = 0; step < steps; ++step) {
      if constexpr (time_dependent<S>()) x.t = clock_.at(n);
      else x.t = 0.0;
      step_one(x, n, step);
      ++n;
      const ObservableView<D> v = view(x, clock_.at(n));
      if (o_.window_every_step && n >= o_.window_first && n <= o_.window_last)
        accumulate(slot, v, c);
      if (M::stops(v, c)) return n;
    }
    // The tile's flag came from these very steps (the same function on the same bits): not
    // finding it again is a bug, never a result.
    throw std::logic_error("FormulaTracker::rerun: the stop flagged in the tile did not recur");
  }

  // An adaptive lane i of tile t after an accepted step: whether the condition holds at its
  // own time.
  bool stops_now(const Tile& t, int i) const {
    if constexpr (M::stop)
      return M::stops(view(formula_lane<S, carry>(t, i), t.ad.t[i]), params(t, i));
    return false;
  }

  // The condition held at the end of the step d (from d.t0 to t_end_of_step, state `end`) and
  // not at its start: the first time it holds, to adjacent doubles, by bisection on the step's
  // continuous extension (one change of the condition inside a step assumed, as a fixed-step
  // method assumes it between steps). x: the state there, from `end` and the extension.
  template <class Dense>
  static double locate_stop(const Dense& d, double t_end_of_step, const LaneState<D>& end,
                            const Params& c, LaneState<D>& x) {
    auto at = [&](double time) {
      LaneState<D> y = end;
      const auto v = d.at_time(time);
      for (int k = 0; k < D; ++k) y.q[k] = v.q[k], y.p[k] = v.p[k];
      y.z = v.z, y.mu = v.mu;
      y.t = time;
      return y;
    };
    double lo = d.t0, hi = t_end_of_step;
    x = end;
    x.t = hi;
    for (int k = 0; k < 128; ++k) {
      const double mid = lo + 0.5 * (hi - lo);
      if (!(mid > lo && mid < hi)) break;
      const LaneState<D> y = at(mid);
      if (M::stops(view(y, mid), c)) hi = mid, x = y;
      else lo = mid;
    }
    return hi;
  }

  // An adaptive lane in `slot` stopped at time x.t in state x: flagged for the runner's look.
  void hold_stop(int slot, const LaneState<D>& x) {
    a_.hit[slot] = 1;
    held_[slot] = x;
  }
  const LaneState<D>& held_stop(int slot) const { return held_[slot]; }

  // An adaptive lane's sample of observe_window without trajectory, at nominal step n (from its
  // step's continuous extension: engine/dense_samples.hpp).
  void window_sample(int slot, std::int64_t n, const LaneState<D>& x, const Params& c) {
    accumulate(slot, view(x, clock_.at(n)), c);
  }

  // The exit channel of a lane stopped in state x (1, 2, …), 0 when the formula gives none.
  static int exit_of(const LaneState<D>& x, double time, const Params& c) {
    const double e = M::exit(view(x, time), c);
    return e >= 1.0 && e <= 32767.0 && e == std::floor(e) ? static_cast<int>(e) : 0;
  }

  // A trajectory sample: traj_<name>, and the window's statistics when it lies in the window.
  void record_sample(int slot, std::int64_t point, std::int64_t sample, std::int64_t n,
                     const LaneState<D>& x, const Params& c) {
    if constexpr (M::observables > 0) {
      double v[K];
      M::observe(view(x, clock_.at(n)), c, v);
      for (int k = 0; k < Formulas::observables(); ++k)
        if (o_.trajectory[k] >= 0) column(o_.trajectory[k], point)[sample] = v[k];
      if (o_.window && n >= o_.window_first && n <= o_.window_last) add(slot, v);
    }
  }

  // The lane's values, when it finishes (at t_end, at its stop or when it failed).
  void finish(int slot, const LaneBook<D>& b, const LaneState<D>& x, const Params& c,
              LaneStatus status, bool stopped, int exit) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const bool failed = status == LaneStatus::breakdown || status == LaneStatus::undefined_at_start;
    if constexpr (M::observables > 0) {
      double v[K];
      // An adaptive lane's b.n counts its attempts; its own time is x.t.
      const double time = adaptive_method<Method>() ? x.t : clock_.at(b.n);
      M::observe(view(x, time), c, v);
      for (int k = 0; k < Formulas::observables(); ++k) {
        column(o_.final_value[k], b.point)[0] = failed ? nan : v[k];
        if (!o_.window) continue;
        const bool none = status != LaneStatus::ok || a_.count[slot] == 0.0 || a_.nan[slot] != 0.0;
        column(o_.mean[k], b.point)[0] = none ? nan : a_.sum[k][slot] / a_.count[slot];
        column(o_.min[k], b.point)[0] = none ? nan : a_.min[k][slot];
        column(o_.max[k], b.point)[0] = none ? nan : a_.max[k][slot];
      }
    }
    const double stop_time = adaptive_method<Method>() ? x.t : clock_.at(b.n);
    if (o_.stop) column(o_.stop_time, b.point)[0] = stopped ? stop_time : nan;
    if (o_.exits) column(o_.stop_exit, b.point)[0] = stopped ? exit : 0;
    if (stopped && plan_.samples > 0) {
      // After the stop there is no trajectory: NaN, as after a failure (lane_writer.hpp).
      for (auto s = b.samples_recorded; s < plan_.samples; ++s) {
        for (int var : plan_.map.traj_vars)
          if (var >= 0) column(var, b.point)[s] = nan;
        if (plan_.map.traj_H >= 0) column(plan_.map.traj_H, b.point)[s] = nan;
        for (int k = 0; k < o_.observables; ++k) column(o_.trajectory[k], b.point)[s] = nan;
      }
    }
    // A failed lane, or a healthy one that ended before t_end without a stop (its basin settled
    // with early stop): its observables' samples after its last one are NaN, as its state's.
    if (!stopped && plan_.samples > 0)
      for (auto s = b.samples_recorded; s < plan_.samples; ++s)
        for (int k = 0; k < o_.observables; ++k) column(o_.trajectory[k], b.point)[s] = nan;
  }

 private:
  struct Snapshot {
    alignas(64) double q[D][W];
    alignas(64) double p[D][W];
    alignas(64) double kq[D][W];
    alignas(64) double z[W];
    alignas(64) double mu[W];
    alignas(64) double numerator[W];
    alignas(64) double denominator[W];
    alignas(64) double folds[W];
    alignas(64) double broken[W];
    double sum[K][2 * W], min[K][2 * W], max[K][2 * W], count[2 * W], nan[2 * W];
  };

  Params params(const Tile& t, int i) const {
    if constexpr (Uniform) return uniform_;
    else return t.params(i);
  }

  void accumulate(int slot, const ObservableView<D>& v, const Params& c) {
    if constexpr (M::observables > 0) {
      double values[K];
      M::observe(v, c, values);
      add(slot, values);
    }
  }

  void add(int slot, const double* v) {
    double nan_seen = a_.nan[slot];
    for (int k = 0; k < Formulas::observables(); ++k) {
      a_.sum[k][slot] = a_.sum[k][slot] + v[k];
      a_.min[k][slot] = v[k] < a_.min[k][slot] ? v[k] : a_.min[k][slot];
      a_.max[k][slot] = v[k] > a_.max[k][slot] ? v[k] : a_.max[k][slot];
      nan_seen = v[k] != v[k] ? 1.0 : nan_seen;
    }
    a_.nan[slot] = nan_seen;
    a_.count[slot] = a_.count[slot] + 1.0;
  }

  double* column(int c, std::int64_t point) {
    auto& col = out_.columns[static_cast<std::size_t>(c)];
    auto width = plan_.columns[static_cast<std::size_t>(c)].width;
    return col.data() + (point - out_.range.begin) * width;
  }

  const RunPlan& plan_;
  const ObservePlan& o_;
  BlockResults& out_;
  LaneClock clock_;
  Params uniform_;
  FormulaSteps<K, W> a_;  // the every-step work's, handed to a step kernel's step loop
  Snapshot snapshot_[M::stop ? 2 : 1];
  LaneState<D> held_[M::stop && adaptive_method<Method>() ? 2 * W : 1];  // hold_stop
};

}  // namespace cs
