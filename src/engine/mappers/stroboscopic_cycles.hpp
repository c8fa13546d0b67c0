// Stroboscopic cycles (a basin mapper, basin_mapper.hpp): a forced lane is sampled at
// t_start + k·T (the stroboscopic map, T = measures.basin.period) and settles on a period-m cycle
// of that map, m ≤ max_period, by the anchored runs of CycleTracker (attractor_search.hpp).
// Nothing is screened: the samples are due looks (next_look), taken in scalar code.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>

#include "engine/attractor_search.hpp"
#include "engine/mappers/basin_mapper.hpp"

namespace cs {

template <int D, int W>
class StroboscopicCycles {
  static constexpr int N = 2 * D;

 public:
  StroboscopicCycles(const RunPlan& plan, bool active, LaneClock clock)
      : plan_(plan), active_(active), clock_(clock) {
    // A tracker is ~1 KB: kept per slot here, not in the lane's books, which are copied when a
    // lane moves (copying it with every book made the double well's map 8 % slower).
    if (active) trackers_ = std::make_unique<CycleTracker<N>[]>(2 * W);
  }

  bool active() const { return active_; }

  void clear(int slot) {
    if (slot < W) trackers_[slot] = CycleTracker<N>{};  // the next lane's samples start afresh
  }

  template <class Lane, class Params>
  void look(int slot, std::int64_t n, const Lane& x, const Params&, Settlement<N>& s) {
    const std::int64_t every = plan_.attractors.sample_steps;
    if (n % every != 0) return;
    CycleTracker<N>& cycle = trackers_[slot];
    typename CycleTracker<N>::Point point;
    for (int d = 0; d < D; ++d) point[d] = x.q[d], point[D + d] = x.p[d];
    if (const int m = cycle.feed(point, plan_.attractors)) {
      s.settled = true;
      s.period = m;
      s.point = cycle.representative(m, plan_.attractors);
      s.settle_time = clock_.at(cycle.settled_start() * every);
    }
  }

  template <class Lane, class Params>
  void arm(int, const Lane&, const Params&, const Settlement<N>&) {}
  void disarm(int) {}
  template <class Params>
  bool refuses(const Settlement<N>&, const Params&) const { return false; }
  void move(int from, int to) { trackers_[to] = trackers_[from]; }

  std::int64_t next_look(std::int64_t n) const {
    const std::int64_t every = plan_.attractors.sample_steps;
    return (n / every + 1) * every;
  }

 private:
  const RunPlan& plan_;
  bool active_;
  LaneClock clock_;
  std::unique_ptr<CycleTracker<N>[]> trackers_;  // per slot, main and finisher
};

}  // namespace cs
