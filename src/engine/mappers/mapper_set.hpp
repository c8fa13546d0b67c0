// The basin mappers of a run, called in one fixed order (the first that settles a lane wins):
// the anchor test at every look, or the stroboscopic cycles when measures.basin.period is given;
// and the energy trap wherever K has one (unless measures.basin.exact_trap = false); last, the
// recurrences (any attractor, RunPlan::recurrence) for lanes the others have not settled. A new mapper is one more file in this folder
// and one more member here; the block runner calls only this set (basin_mapper.hpp). An
// adaptive method's stroboscopic map comes from its steps' dense output (look_stroboscopic).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "engine/mappers/anchor_test.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "engine/mappers/energy_trap.hpp"
#include "engine/mappers/recurrences.hpp"
#include "engine/mappers/stroboscopic_cycles.hpp"

namespace cs {

template <Scene S, bool Uniform, int W>
class MapperSet {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D;
  using Params = ParamsOf<S, double>;

 public:
  MapperSet(const RunPlan& plan, LaneClock clock, const Params& uniform)
      : anchors_(plan, autonomous(plan), clock),
        trap_(plan, mapping(plan) && plan.spec.measures.basin->exact_trap, clock, uniform),
        strobe_(plan, mapping(plan) && !autonomous(plan), map_clock(plan, clock)),
        recur_(plan, mapping(plan) && plan.recurrence.enabled, map_clock(plan, clock)),
        dense_strobe_(mapping(plan) && plan.attractors.dense_strobe) {}

  [[gnu::always_inline]] void clear(int slot) {
    each([&](auto& m) { m.clear(slot); });
  }

  // A healthy lane at step n: each mapper in turn, until one settles it (settle_with).
  // An adaptive lane's stroboscopic map is sampled inside its steps (look_stroboscopic): its
  // looks are not on the map, and the mappers that sample it skip them.
  // Not inlined: it holds every mapper's look, and the runner calls it from three places (a
  // lane's load, a look, the finisher), each of which had its own copy to compile; a call per
  // look costs nothing beside the look itself.
  template <class Lane>
  [[gnu::noinline]] void look(int slot, std::int64_t n, const Lane& x, const Params& c, Settlement<N>& s) {
    each([&](auto& m) {
      if (dense_strobe_ && samples_map(m)) return;
      settle_with(m, slot, n, x, c, s);
    });
    // A lane in a well the trap missed: the anchor test finds where it settles, from here.
    if (trap_.active() && trap_.take_lost() && anchors_.active() && !anchors_.armed(slot))
      anchors_.arm(slot, x, c, s);
  }

  // An adaptive lane's stroboscopic sample k, at t_start + k·period (engine/dense_samples.hpp):
  // the mappers that sample the map, in their order (not inlined, as look()).
  template <class Lane>
  [[gnu::noinline]] void look_stroboscopic(int slot, std::int64_t k, const Lane& x, const Params& c,
                         Settlement<N>& s) {
    each([&](auto& m) {
      if (samples_map(m)) settle_with(m, slot, k, x, c, s);
    });
  }

  // After the look at load; a lane settled at once is never screened. The anchor test is not
  // armed for a lane the energy trap alone decides (EnergyTrap::decides_alone): its screen then
  // costs nothing where every lane is the trap's (the double well's map).
  template <class Lane>
  void arm(int slot, const Lane& x, const Params& c, const Settlement<N>& s) {
    if (s.settled) return;
    const bool trapped = trap_.active() && trap_.decides_alone(x, c);
    if (anchors_.active() && !trapped) anchors_.arm(slot, x, c, s);
    if (recur_.active() && !trapped) recur_.arm(slot, x, c, s);
    if (trap_.active()) trap_.arm(slot, x, c, s);
    if (strobe_.active()) strobe_.arm(slot, x, c, s);
  }

  [[gnu::always_inline]] void disarm(int slot) {
    each([&](auto& m) { m.disarm(slot); });
  }

  // Whether a lane flag can be raised now (else the runner's screen loop skips flag()).
  bool flagging() const { return trap_.active() && trap_.armed_lanes() > 0; }

  // The lane flags of the mappers that screen with one (inside the runner's screen loop)…
  template <class Tile>
  [[gnu::always_inline]] LookInt flag(const Tile& t, int i) const {
    LookInt f = 0;
    if (trap_.active()) f |= trap_.flag(t, i);
    return f;
  }

  // … then the screens of those that make a pass of their own.
  template <class Tile>
  void screen(const Tile& t, LookInt* attention) {
    if (anchors_.active()) anchors_.screen(t, attention);
    if (recur_.active()) recur_.screen(t, attention);
  }

  [[gnu::always_inline]] void move(int from, int to) {
    each([&](auto& m) { m.move(from, to); });
  }

  [[gnu::always_inline]] std::int64_t next_look(std::int64_t n) const {
    std::int64_t next = std::numeric_limits<std::int64_t>::max();
    each([&](const auto& m) {
      if (!(dense_strobe_ && samples_map(m))) next = std::min(next, m.next_look(n));
    });
    return next;
  }

  TrapVerdict trap_verdict(const Params& c) const { return trap_.verdict(c); }

  // The lane's record for the attractor table and why it is undecided (Recurrences::record).
  void recurrence_record(int slot, bool failed, const Settlement<N>& s, double* out,
                         UndecidedReason& why) const {
    recur_.record(slot, failed, s, out, why);
  }

 private:
  static bool mapping(const RunPlan& plan) { return plan.map.basin >= 0; }
  static bool autonomous(const RunPlan& plan) {
    return mapping(plan) && !plan.spec.measures.basin->period.has_value();
  }

  // The clock of the mappers that sample the stroboscopic map: an adaptive lane's samples are
  // counted, k at t_start + k·period (RunPlan's dense_strobe); else the steps' own.
  static LaneClock map_clock(const RunPlan& plan, LaneClock steps) {
    if (!mapping(plan) || !plan.attractors.dense_strobe) return steps;
    return LaneClock{plan.spec.t_start, *plan.spec.measures.basin->period};
  }

  // Whether mapper m samples the stroboscopic map (when there is one).
  template <class M>
  static constexpr bool samples_map(const M&) {
    return std::is_same_v<M, StroboscopicCycles<D, W>> || std::is_same_v<M, Recurrences<D, W>>;
  }

  // Mapper m looks at the lane at step (or sample) n, unless it has settled. A settlement
  // another mapper refuses (it knows the point is no attractor) is undone, and m stops looking.
  template <class M, class Lane>
  [[gnu::always_inline]] void settle_with(M& m, int slot, std::int64_t n, const Lane& x,
                                          const Params& c, Settlement<N>& s) {
    if (s.settled) return;
    m.look(slot, n, x, c, s);
    // The trap settles at a well's minimum, which no mapper refuses: asking cost the double
    // well's map 2 % of its bookkeeping.
    constexpr bool the_trap = std::is_same_v<M, EnergyTrap<S, Uniform, W>>;
    if (!the_trap && s.settled && refused(s, c)) {
      s = Settlement<N>{};
      m.disarm(slot);
    }
  }

  bool refused(const Settlement<N>& s, const Params& c) const {
    bool refused = false;
    each([&](const auto& m) { refused = refused || m.refuses(s, c); });
    return refused;
  }

  // The active mappers, in order.
  template <class F>
  [[gnu::always_inline]] void each(F&& f) {
    if (anchors_.active()) f(anchors_);
    if (trap_.active()) f(trap_);
    if (strobe_.active()) f(strobe_);
    if (recur_.active()) f(recur_);
  }
  template <class F>
  [[gnu::always_inline]] void each(F&& f) const {
    if (anchors_.active()) f(anchors_);
    if (trap_.active()) f(trap_);
    if (strobe_.active()) f(strobe_);
    if (recur_.active()) f(recur_);
  }

  AnchorTest<D, W> anchors_;
  EnergyTrap<S, Uniform, W> trap_;
  StroboscopicCycles<D, W> strobe_;
  Recurrences<D, W> recur_;
  bool dense_strobe_;
};

}  // namespace cs
