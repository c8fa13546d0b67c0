// The anchor test (a basin mapper, basin_mapper.hpp): an autonomous lane settles on the fixed
// point it stays near. At every look, a lane's run near its anchor (the point where the run began)
// grows by one look while the lane stays within the tolerance (max norm, angles modulo their
// period), and starts again from where the lane is when it does not; `dwell` looks in a run settle
// the lane, from the run's first look. Measured against the fixed anchor, not the previous look:
// a lane creeping past a saddle by less than the tolerance per look would otherwise pass for
// settled. With an adaptive method (plan.method.adaptive) the run is measured in the lanes' own
// time: a lane settles once it has stayed near its anchor for `dwell` time units (its looks are
// `chunk` attempts apart, which span any time).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/attractor_search.hpp"
#include "engine/mappers/basin_mapper.hpp"

namespace cs {

template <int D, int W>
class AnchorTest {
  static constexpr int N = 2 * D;

 public:
  AnchorTest(const RunPlan& plan, bool active, LaneClock clock)
      : plan_(plan), active_(active), timed_(plan.method.adaptive), clock_(clock) {
    for (int k = 0; k < N && active; ++k) {
      angle_period_[k] = plan.attractors.angle_period[static_cast<std::size_t>(k)];
      angle_frequency_[k] = angle_period_[k] > 0.0 ? 1.0 / angle_period_[k] : 0.0;
      has_angles_ = has_angles_ || angle_period_[k] > 0.0;
    }
  }

  bool active() const { return active_; }

  void clear(int slot) {
    if (slot >= W) return;
    disarm(slot);
    near_[slot] = 0.0;
    anchor_time_[slot] = 0.0;
    dwell_needed_[slot] = std::numeric_limits<double>::infinity();
    for (int k = 0; k < N; ++k) anchor_[k][slot] = 0.0;
  }

  // Settles a lane whose run has lasted `dwell` looks (only main lanes are screened).
  template <class Lane, class Params>
  void look(int slot, std::int64_t n, const Lane& x, const Params&, Settlement<N>& s) {
    if constexpr (requires { x.t; }) {
      if (timed_) {
        if (slot >= W || !(x.t - anchor_time_[slot] >= dwell_needed_[slot])) return;
        settle(x, s);
        s.settle_time = anchor_time_[slot];
        return;
      }
    }
    if (slot >= W || !(near_[slot] >= dwell_needed_[slot])) return;
    settle(x, s);
    s.settle_time = clock_.at(n - static_cast<std::int64_t>(near_[slot]) * plan_.chunk);
  }

  template <class Lane>
  void settle(const Lane& x, Settlement<N>& s) const {
    typename CycleTracker<N>::Point point;
    for (int d = 0; d < D; ++d) point[d] = x.q[d], point[D + d] = x.p[d];
    s.settled = true;
    s.period = 1;
    s.point = CycleTracker<N>::reduced(point, plan_.attractors);
  }

  // A run starts afresh at x.
  template <class Lane, class Params>
  void arm(int slot, const Lane& x, const Params&, const Settlement<N>&) {
    if (slot >= W) return;
    for (int d = 0; d < D; ++d) anchor_[d][slot] = x.q[d], anchor_[D + d][slot] = x.p[d];
    near_[slot] = 0.0;
    dwell_needed_[slot] = plan_.attractors.dwell_samples;
    if (timed_) {
      if constexpr (requires { x.t; }) anchor_time_[slot] = x.t;
      dwell_needed_[slot] = plan_.spec.measures.basin->dwell;
    }
    armed_count_ += !armed_[slot];
    armed_[slot] = true;
  }

  bool armed(int slot) const { return slot < W && armed_[slot]; }

  void disarm(int slot) {
    if (slot >= W) return;
    dwell_needed_[slot] = std::numeric_limits<double>::infinity();
    armed_count_ -= armed_[slot];
    armed_[slot] = false;
  }

  // Branch-free over the tile, like the runner's screen; angles folded only where there are.
  template <class Tile>
  void screen(const Tile& t, LookInt* attention) {
    if (armed_count_ == 0) return;  // e.g. every lane the energy trap's alone
    if (has_angles_) screen_lanes<true>(t, attention);
    else screen_lanes<false>(t, attention);
  }

  template <class Params>
  bool refuses(const Settlement<N>&, const Params&) const { return false; }
  void move(int, int) {}  // the finisher's last look is at t_end: no run to continue
  std::int64_t next_look(std::int64_t) const { return std::numeric_limits<std::int64_t>::max(); }

 private:
  template <bool kAngles, class Tile>
  void screen_lanes(const Tile& t, LookInt* attention) {
    const double tolerance = plan_.attractors.tolerance;
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LookInt near = 1;
      for (int d = 0; d < D; ++d) {
        near &= std::fabs(folded<kAngles>(t.q[d][i] - anchor_[d][i], d)) <= tolerance;
        near &= std::fabs(folded<kAngles>(t.p[d][i] - anchor_[D + d][i], D + d)) <= tolerance;
      }
      near_[i] = near ? near_[i] + 1.0 : 0.0;
      for (int d = 0; d < D; ++d) {
        anchor_[d][i] = near ? anchor_[d][i] : t.q[d][i];
        anchor_[D + d][i] = near ? anchor_[D + d][i] : t.p[d][i];
      }
      if constexpr (Tile::adaptive) {
        anchor_time_[i] = near ? anchor_time_[i] : t.ad.t[i];
        attention[i] |= t.ad.t[i] - anchor_time_[i] >= dwell_needed_[i];
      } else {
        attention[i] |= near_[i] >= dwell_needed_[i];
      }
    }
  }

  // A difference of variable k folded into [−period/2, period/2] if k is an angle (as
  // phase_difference, without a branch: the frequency of a non-angle is 0).
  template <bool kAngles>
  double folded(double difference, int k) const {
    if constexpr (!kAngles) return difference;  // 0·nearbyint(0): the same bits, for nothing
    else return difference - angle_period_[k] * std::nearbyint(difference * angle_frequency_[k]);
  }

  const RunPlan& plan_;
  bool active_;
  bool timed_;  // an adaptive method's lanes: dwell in time units, from anchor_time_
  LaneClock clock_;
  double angle_period_[N] = {}, angle_frequency_[N] = {};
  bool has_angles_ = false;
  alignas(64) double anchor_[N][W];     // where each lane's current run near a point began
  alignas(64) double near_[W];          // looks since then, all within the tolerance
  alignas(64) double dwell_needed_[W];  // looks that settle a lane (∞: not searching; timed:
                                        // time units)
  alignas(64) double anchor_time_[W];   // timed: the lane's time at its anchor
  bool armed_[W] = {};                  // searching (dwell_needed_ finite)
  int armed_count_ = 0;
};

}  // namespace cs
