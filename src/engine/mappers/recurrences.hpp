// Recurrences (a basin mapper, basin_mapper.hpp): any attractor — a limit cycle, a torus, a
// chaotic set — found as Attractors.jl's recurrence mapper finds it, one lane at a time
// (engine/recurrence/recurrence_tracker.hpp). A lane is sampled at every look (autonomous: its
// screen asks for a look at every chunk) or on the stroboscopic map (period: due looks); each
// sample is binned into the run's cells (RunPlan::recurrence), and the lane settles when its
// cells recur. It comes last in MapperSet's order and is not armed for lanes the energy trap
// decides alone, so a lane the fixed-point mappers settle keeps their settlement; and its first
// sample is taken when they could first have settled the lane (after `dwell`: the anchor test's
// or the stroboscopic cycles'), so that the lanes they settle then cost it nothing (the forced
// Duffing's map: 3 % of its time when every sample from t = 0 was binned).
//
// A settlement names no point of a cycle (period 0) but the cells: the centre of the smallest
// located key as its point, and for the attractor table the lane's record (record()): that key,
// the count of located cells and a bottom-k sketch of them.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>

#include "engine/mappers/basin_mapper.hpp"
#include "engine/recurrence/cell_grid.hpp"
#include "engine/recurrence/recurrence_search.hpp"
#include "engine/recurrence/recurrence_tracker.hpp"

namespace cs {

template <int D, int W>
class Recurrences {
  static constexpr int N = 2 * D;

 public:
  Recurrences(const RunPlan& plan, bool active, LaneClock clock)
      : active_(active), timed_(plan.method.adaptive), clock_(clock) {
    if (!active) return;
    const RecurrenceSearch& r = plan.recurrence;
    std::array<double, N> lower{}, upper{}, size{}, period{};
    for (int k = 0; k < N; ++k) {
      const auto i = static_cast<std::size_t>(k);
      lower[k] = r.lower[i], upper[k] = r.upper[i], period[k] = r.angle_period[i];
      size[k] = r.angle_period[i] > 0.0 ? r.angle_period[i] / static_cast<double>(r.cells[i])
                                        : r.cell_size[i];
    }
    grid_ = CellGrid<N>(lower, upper, size, period);
    options_.recurrences = r.recurrences;
    options_.locate = r.locate;
    options_.max_lost = r.max_lost;
    options_.max_cells = static_cast<std::size_t>(r.max_cells);
    every_ = plan.attractors.sample_steps;
    start_ = static_cast<std::int64_t>(plan.attractors.dwell_samples) * every_;
    stroboscopic_ = plan.spec.measures.basin->period.has_value();
    trackers_ = std::make_unique<RecurrenceTracker<N>[]>(2 * W);
    for (int s = 0; s < 2 * W; ++s) trackers_[s].reset(options_.max_cells);
  }

  bool active() const { return active_; }

  void clear(int slot) {
    trackers_[slot].reset(options_.max_cells);  // keeps its table for the next lane
    next_[slot] = -1;
    if (slot < W) disarm(slot);
  }

  // Feeds the lane's sample when one is due; settles it when its cells recur.
  template <class Lane, class Params>
  void look(int slot, std::int64_t n, const Lane& x, const Params&, Settlement<N>& s) {
    if (n != next_[slot]) return;
    feed(slot, n, x);
    RecurrenceTracker<N>& tracker = trackers_[slot];
    if (tracker.state() == Recurrence::settled) {
      s.settled = true;
      s.period = 0;
      s.point = grid_.centre(tracker.representative());
      s.settle_time = clock_.at(start_ + tracker.settle_sample() * every_);
      // An adaptive method's looks are attempts apart, not time: the time of this look, a bound
      // (its stroboscopic samples are counted, and the clock above times them).
      if constexpr (requires { x.t; })
        if (timed_ && !stroboscopic_) s.settle_time = x.t;
    } else if (finished(tracker.state())) {
      next_[slot] = -1;  // gave up (left the box, too many cells): record() says why
      if (slot < W) disarm(slot);
    }
  }

  // The lane's first sample is due at step start_.
  template <class Lane, class Params>
  void arm(int slot, const Lane& x, const Params&, const Settlement<N>&) {
    if (slot >= W) return;
    next_[slot] = start_;
    if (start_ == 0) feed(slot, 0, x);
    looks_to_start_[slot] = static_cast<LookInt>(start_ / every_);
    armed_count_ += !armed_[slot];
    armed_[slot] = 1;
  }

  void disarm(int slot) {
    if (slot >= W) return;
    armed_count_ -= armed_[slot] != 0;
    armed_[slot] = 0;
  }

  // Autonomous: an armed lane is due at every look from its start. Stroboscopic: due looks
  // (next_look).
  template <class Tile>
  void screen(const Tile&, LookInt* attention) {
    if (armed_count_ == 0 || stroboscopic_) return;
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      looks_to_start_[i] -= looks_to_start_[i] > 0;
      attention[i] |= armed_[i] & (looks_to_start_[i] <= 0);
    }
  }

  template <class Params>
  bool refuses(const Settlement<N>&, const Params&) const {
    return false;
  }

  void move(int from, int to) {
    std::swap(trackers_[from], trackers_[to]);
    next_[to] = next_[from];
  }

  std::int64_t next_look(std::int64_t n) const {
    if (!stroboscopic_) return std::numeric_limits<std::int64_t>::max();
    return n < start_ ? start_ : (n / every_ + 1) * every_;
  }

  // The lane's record for the attractor table (RecurrenceSearch::kRecordWidth values, NaN
  // unless it settled here) and, if it is undecided, why.
  void record(int slot, bool failed, const Settlement<N>& s, double* out,
              UndecidedReason& why) const {
    for (int k = 0; k < RecurrenceSearch::kRecordWidth; ++k) out[k] = std::nan("");
    const RecurrenceTracker<N>& tracker = trackers_[slot];
    if (failed) {
      why = UndecidedReason::diverged;
      return;
    }
    if (s.settled) {
      why = UndecidedReason::decided;
      if (s.period != 0) return;
      out[0] = static_cast<double>(tracker.representative());
      out[1] = static_cast<double>(tracker.located_cells());
      const auto sketch = tracker.sketch(RecurrenceSearch::kSketch);
      for (std::size_t k = 0; k < sketch.size(); ++k) out[2 + k] = static_cast<double>(sketch[k]);
      return;
    }
    switch (tracker.state()) {
      case Recurrence::searching:  // never armed, or armed and still finding new cells
        why = tracker.samples() == 0 && next_[slot] < 0 ? UndecidedReason::not_tracked
                                                        : UndecidedReason::no_recurrence;
        return;
      case Recurrence::locating: why = UndecidedReason::not_located; return;
      case Recurrence::left_box: why = UndecidedReason::left_box; return;
      case Recurrence::too_many_cells: why = UndecidedReason::too_many_cells; return;
      case Recurrence::diverged: why = UndecidedReason::diverged; return;
      case Recurrence::settled: why = UndecidedReason::decided; return;
    }
  }

 private:
  template <class Lane>
  void feed(int slot, std::int64_t n, const Lane& x) {
    double point[N];
    for (int d = 0; d < D; ++d) point[d] = x.q[d], point[D + d] = x.p[d];
    trackers_[slot].feed(point, grid_, options_);
    next_[slot] = n + every_;
  }

  bool active_;
  bool timed_;
  LaneClock clock_;
  CellGrid<N> grid_;
  RecurrenceOptions options_;
  std::int64_t every_ = 1, start_ = 0;  // steps between samples; the step of the first
  bool stroboscopic_ = false;
  std::unique_ptr<RecurrenceTracker<N>[]> trackers_;  // per slot, main and finisher
  std::int64_t next_[2 * W] = {};  // the step of the lane's next sample (−1: none)
  alignas(64) LookInt armed_[W] = {};
  alignas(64) LookInt looks_to_start_[W] = {};  // autonomous: chunks until the first sample
  int armed_count_ = 0;
};

}  // namespace cs
