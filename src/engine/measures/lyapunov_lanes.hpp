// The lyapunov measure's part of the block runner: the tangents of the main and finisher tiles,
// seeded when a lane is loaded, moved with it, and turned into the `lyapunov` column when it
// finishes (tangent_lyapunov.hpp). Without Carry::tangent every call is empty and vanishes.
//
// The exponent's interval (docs/lyapunov.md): [t_start, the lane's last step] — t_end, its stop
// (measures.stop) or where its basin settled — or, with measures.observe_window, the part of
// that interval inside the window's samples [n_a, n_b] (ObservePlan::window_first, _last): the
// tangent still starts at t_start, so it has aligned with the most expanding direction by n_a,
// and ln‖v‖ is read at n_a and at the end. A lane that stops after a chunk's start is stepped
// again from a snapshot of its tangent with the state (rerun_*), as FormulaTracker does.
// An adaptive lane (dop853) steps to times of its own: its window's ends t_a = t_start + n_a·h
// and t_b = min(t_start + n_b·h, t_end) fall inside its steps, and ln‖v‖ there is read on the
// step's continuous extension on duals (in_step, from the runner's dense_step, as the stop's
// tangent: at_stop), or from the step's end where the end is the mark's time.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <type_traits>

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
  void finish(int, LaneBook<S::dof>&, LaneStatus, double) {}
  double next_mark(int) const { return INFINITY; }
  bool marks_in_steps() const { return false; }
  void in_step(bool, int, double) {}
};

template <Scene S, class Method, Carry carry, int W>
requires(carry.tangent) class LyapunovLanes<S, Method, carry, W> {
  static constexpr int D = S::dof;
  static constexpr bool with_z = tangent_has_z<S>();
  using Tile = LaneTile<S, Method, W>;
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;

  // ln‖v‖ = folds·256 ln 2 + log_norm at a step, kept apart as lyapunov_value keeps them.
  struct Mark {
    double folds = 0.0, log_norm = 0.0;
    bool set = false;
  };

 public:
  LyapunovLanes(const RunPlan& plan, BlockResults& out)
      : plan_(plan),
        out_(out),
        window_(plan.observe.window),
        n_a_(window_ ? plan.observe.window_first : 0),
        n_b_(window_ ? plan.observe.window_last : plan.spec.steps),
        t_a_(plan.spec.t_start + static_cast<double>(n_a_) * plan.spec.h),
        t_b_(std::min(plan.spec.t_start + static_cast<double>(n_b_) * plan.spec.h,
                      plan.spec.t_end)) {}

  // Main slot i now holds a fresh lane at x (its force cache set by Method::start).
  void seed(int i, const LaneState<D>& x, const Params& c) {
    main_.set_lane(i, seeded_tangent<S, Method>(x, c, plan_.lyapunov_seed));
    mark_a_[i] = mark_b_[i] = Mark{};
    if (window_ && n_a_ == 0) mark_a_[i] = Mark{0.0, plan_.lyapunov_log_norm0, true};
  }
  void clear(bool main, int i) {
    (main ? main_ : fin_).set_lane(i, LaneTangent<D>{});
    const int slot = main ? i : W + i;
    mark_a_[slot] = mark_b_[slot] = Mark{};
  }
  void move(int i, int j) {
    fin_.set_lane(j, main_.lane(i));
    mark_a_[W + j] = mark_a_[i], mark_b_[W + j] = mark_b_[i];
  }

  // Advances tile t (main or finisher) by `steps`; its lanes were at step counts base[i].
  // after_step(s) as advance() calls it. With a stop, the tangents are kept first (rerun_*).
  template <bool Uniform, class AfterStep>
  void advance(Tile& t, bool main, const std::int64_t* base, int steps, const Params& uniform,
               const Coef& uniform_coef, double t_start, double h, AfterStep&& after_step) {
    TangentTile<S, W>& g = main ? main_ : fin_;
    const int which = main ? 0 : 1;
    if (plan_.observe.stop) std::memcpy(&snapshot_[which], &g, sizeof g);
    bool marks = false;  // does this advance pass a window end of some lane?
    if (window_) {
      for (int i = 0; i < W && !marks; ++i)
        marks = passes(base[i], steps, n_a_) || passes(base[i], steps, n_b_);
    }
    if (!marks) {
      advance_with_tangent<S, Method, carry, Uniform>(t, g, steps, uniform, uniform_coef, t_start,
                                                      h, after_step);
      return;
    }
    advance_with_tangent<S, Method, carry, Uniform>(
        t, g, steps, uniform, uniform_coef, t_start, h, [&](int s) {
          for (int i = 0; i < W; ++i) {
            const std::int64_t n = base[i] + s + 1;
            if (n == n_a_ || n == n_b_) mark(which * W + i, n, g.lane(i));
          }
          after_step(s);
        });
  }

  // An adaptive method's tile t (main or finisher) makes `steps` attempts, its tangents with it
  // (AdaptiveTangent); on_dense and watch (the stop's, or nullptr) as advance_adaptive takes
  // them. With the stop or the window, a step that holds the stop or a window's end has the
  // tangent's continuous extension, read by at_stop and in_step from on_dense.
  template <bool Uniform, class OnDense, class Watch>
  void advance_adaptive_tile(Tile& t, bool main, int steps, const Params& uniform,
                             OnDense&& on_dense, Watch&& watch) {
    AdaptiveTangent<S, W, carry.z || S::z_feeds_back, carry.mu && !S::kz_constant> tangent{
        main ? main_ : fin_};
    tangent.want_dense = !std::is_null_pointer_v<std::remove_cvref_t<Watch>> || window_;
    for (int i = 0; i < W; ++i) tangent.mark_at[i] = next_mark(main ? i : W + i);
    marks_in_advance_ = tangent.mark_at;
    dense_tangent_ = [&tangent](double te, double* v) {
      const auto y = tangent.dense.at_time(te);
      for (int d = 0; d < D; ++d) v[d] = y.q[d].d, v[D + d] = y.p[d].d;
      if constexpr (with_z) v[2 * D] = y.z.d;
    };
    advance_adaptive<S, Method, carry, Uniform>(t, steps, uniform, [](int) {}, on_dense, watch,
                                                tangent);
    dense_tangent_ = nullptr;
    marks_in_advance_ = nullptr;
  }

  // An adaptive lane with observe_window: whether its steps must stop by the window's ends
  // (the runner then builds dense output), and the next end lane `slot` has not marked yet
  // (+∞ when none).
  bool marks_in_steps() const { return window_ && adaptive_method<Method>(); }
  double next_mark(int slot) const {
    if (!marks_in_steps()) return INFINITY;
    if (!mark_a_[slot].set) return t_a_;
    return mark_b_[slot].set ? INFINITY : t_b_;
  }

  // From on_dense of advance_adaptive_tile (after at_stop, if the lane stopped): lane i of the
  // main tile or the finisher took a step (or stopped) reaching t_lane; ln‖v‖ at the window's
  // ends up to t_lane, read on the step's extension, or from the tangent itself at t_lane (the
  // step's end, or the stop's tangent). The fold runs after on_dense, so the extension's
  // tangent has the scale of folds[i].
  void in_step(bool main, int i, double t_lane) {
    const TangentTile<S, W>& g = main ? main_ : fin_;
    const int slot = main ? i : W + i;
    for (double te = next_mark(slot); te <= t_lane; te = next_mark(slot)) {
      double v[2 * D + 1] = {};
      if (te == t_lane) {
        for (int k = 0; k < 2 * D + 1; ++k) v[k] = g.v[k][i];
      } else {
        dense_tangent_(te, v);
      }
      const Mark m{g.folds[i], log_norm(v), true};
      if (!mark_a_[slot].set && te == t_a_) mark_a_[slot] = m;
      if (!mark_b_[slot].set && te == t_b_) mark_b_[slot] = m;
    }
    if (marks_in_advance_ != nullptr) marks_in_advance_[i] = next_mark(slot);
  }

  // From on_dense of advance_adaptive_tile: lane i of the main tile or the finisher stops at
  // t_stop inside its last step; its tangent there, from the step's extension (it is held
  // there: its later attempts are empty and leave the tangent as it is).
  void at_stop(bool main, int i, double t_stop) {
    TangentTile<S, W>& g = main ? main_ : fin_;
    double v[2 * D + 1] = {};
    dense_tangent_(t_stop, v);
    for (int k = 0; k < 2 * D + 1; ++k) g.v[k][i] = v[k];
  }

  // A lane in `slot` stepped again from the chunk's start (base) to its stop: its tangent from
  // the snapshot, and no marks past base (the tile's advance ran on past the stop).
  void rerun_begin(int slot, std::int64_t base) {
    rerun_ = snapshot_[slot / W].lane(slot % W);
    if (n_a_ > base) mark_a_[slot] = Mark{};
    if (n_b_ > base) mark_b_[slot] = Mark{};
  }
  // Step s of the rerun from step count n (x.t set), with the tile's fold schedule.
  void rerun_step(int slot, LaneState<D>& x, std::int64_t n, int s, int steps, const Params& c,
                  const Coef& k) {
    step_with_tangent<S, Method, carry>(x, rerun_, c, coef_for_tangent<Method>(k));
    if (fold_due(s, steps)) fold_tangent<S>(rerun_);
    if (window_ && (n + 1 == n_a_ || n + 1 == n_b_)) mark(slot, n + 1, rerun_);
  }
  // The rerun stopped: the tangent at the stop, folded as at the end of an advance, into its slot.
  void rerun_end(int slot) {
    fold_tangent<S>(rerun_);
    (slot < W ? main_ : fin_).set_lane(slot % W, rerun_);
  }

  // Slot `lane_slot` (main 0 … W−1, finisher W …) finishes after b.n steps, at time t_lane.
  // NaN where the lane failed or its interval is empty; a healthy lane whose exponent is not
  // finite is flagged through its book (LaneWriter then writes non_finite_output). An adaptive
  // lane's interval is [t_start, t_lane], its own time, or with the window [t_a, the earlier
  // of t_b and t_lane]; a fixed-step lane's n·h.
  void finish(int lane_slot, LaneBook<D>& b, LaneStatus status, double t_lane) {
    double value = std::numeric_limits<double>::quiet_NaN();
    bool nonempty = true;  // the interval holds more than its start
    if (status == LaneStatus::ok && b.n > 0) {
      const LaneTangent<D> w = lane_slot < W ? main_.lane(lane_slot) : fin_.lane(lane_slot - W);
      if (marks_in_steps()) {
        // A lane that ended (t_end, its stop, its basin settled) before t_b, or whose last step
        // to t_end did not build an extension: its end is its last tangent, at t_lane.
        const Mark& a = mark_a_[lane_slot];
        const bool at_b = mark_b_[lane_slot].set;
        const Mark e = at_b ? mark_b_[lane_slot] : Mark{w.folds, log_norm(w.v), true};
        const double t_e = at_b ? t_b_ : t_lane;
        nonempty = a.set && t_e > t_a_;
        if (nonempty)
          value = ((e.folds - a.folds) * kFoldLog + (e.log_norm - a.log_norm)) / (t_e - t_a_);
      } else if (adaptive_method<Method>()) {
        value = lyapunov_value_over<D, with_z>(w.v, w.folds, plan_.lyapunov_log_norm0,
                                               t_lane - plan_.spec.t_start);
      } else if (!window_) {
        value = lyapunov_value<D, with_z>(w.v, w.folds, plan_.lyapunov_log_norm0, b.n,
                                          plan_.spec.h);
      } else {
        const Mark& a = mark_a_[lane_slot];
        const std::int64_t n_e = std::min(b.n, n_b_);
        const Mark e = b.n < n_b_ ? Mark{w.folds, log_norm(w.v), true} : mark_b_[lane_slot];
        if (a.set && e.set && n_e > n_a_)
          value = ((e.folds - a.folds) * kFoldLog + (e.log_norm - a.log_norm)) /
                  (static_cast<double>(n_e - n_a_) * plan_.spec.h);
      }
      if (window_ && !adaptive_method<Method>()) nonempty = n_e_nonempty(b.n);
      if (!std::isfinite(value) && nonempty) b.non_finite = true;
    }
    out_.columns[static_cast<std::size_t>(plan_.map.lyapunov)]
                [static_cast<std::size_t>(b.point - out_.range.begin)] = value;
  }

 private:
  static bool passes(std::int64_t base, int steps, std::int64_t n) {
    return base < n && n <= base + steps;
  }
  bool n_e_nonempty(std::int64_t n) const { return std::min(n, n_b_) > n_a_; }

  static double log_norm(const double* v) {
    double sum = 0.0;
    for (int k = 0; k < 2 * D + (with_z ? 1 : 0); ++k) sum = sum + v[k] * v[k];
    return 0.5 * std::log(sum);
  }
  void mark(int slot, std::int64_t n, const LaneTangent<D>& w) {
    const Mark m{w.folds, log_norm(w.v), true};
    if (n == n_a_) mark_a_[slot] = m;
    if (n == n_b_) mark_b_[slot] = m;
  }

  const RunPlan& plan_;
  BlockResults& out_;
  bool window_;
  std::int64_t n_a_, n_b_;  // the exponent's steps: the window's first and last samples
  double t_a_, t_b_;        // their times, for an adaptive lane (t_b at most t_end)
  TangentTile<S, W> main_{}, fin_{};
  TangentTile<S, W> snapshot_[2]{};  // the tiles' tangents at the start of their last advance
  LaneTangent<D> rerun_{};
  // The tangent at a time inside the step on_dense is called for (at_stop, in_step), during
  // advance_adaptive_tile.
  std::function<void(double, double*)> dense_tangent_;
  double* marks_in_advance_ = nullptr;  // its tangent's mark_at, for the lanes' next ends
  Mark mark_a_[2 * W]{}, mark_b_[2 * W]{};
};

}  // namespace cs
