// The basin mappers of a run, called in one fixed order (the first that settles a lane wins):
// the anchor test at every look, or the stroboscopic cycles when measures.basin.period is given;
// and the energy trap wherever K has one (unless measures.basin.exact_trap = false); last, the
// recurrences (any attractor, RunPlan::recurrence) for lanes the others have not settled. A new mapper is one more file in this folder
// and one more member here; the block runner calls only this set (basin_mapper.hpp). An
// adaptive method's stroboscopic map comes from its steps' dense output (look_stroboscopic).
// The set holds only the mappers of its MapperChoice (mapper_choice.hpp): the others are
// AbsentMapper, never active, and their code is never instantiated.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "engine/mappers/anchor_test.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "engine/mappers/energy_trap.hpp"
#include "engine/mappers/mapper_choice.hpp"
#include "engine/mappers/recurrences.hpp"
#include "engine/mappers/stroboscopic_cycles.hpp"

namespace cs {

// A mapper the runner is not compiled with: never active.
struct AbsentMapper {
  template <class... Args>
  explicit AbsentMapper(const Args&...) {}
  static constexpr bool active() { return false; }
};

template <bool compiled, class Mapper>
using MapperIf = std::conditional_t<compiled, Mapper, AbsentMapper>;

template <Scene S, bool Uniform, int W, MapperChoice M = kEveryMapper>
class MapperSet {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D;
  using Params = ParamsOf<S, double>;
  using Anchors = MapperIf<M.anchors, AnchorTest<D, W>>;
  // The energy trap only where K has one (has_energy_trap: K = Σp²/2 + V(q) + k·z, no t); for
  // any other K it never activates, so a forced or z² scene compiles none of its wells.
  static constexpr bool kTrap = M.trap && has_energy_trap<S>();
  using Trap = MapperIf<kTrap, EnergyTrap<S, Uniform, W>>;
  using Strobe = MapperIf<M.strobe, StroboscopicCycles<D, W>>;
  using Recur = MapperIf<M.recur, Recurrences<D, W>>;

 public:
  MapperSet(const RunPlan& plan, LaneClock clock, const Params& uniform)
      : anchors_(plan, used(plan).anchors, clock),
        trap_(plan, used(plan).trap, clock, uniform),
        strobe_(plan, used(plan).strobe, map_clock(plan, clock)),
        recur_(plan, used(plan).recur, map_clock(plan, clock)),
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
    if constexpr (kTrap) {
      if (trap_.active() && trap_.take_lost()) {
        if constexpr (M.anchors)
          if (anchors_.active() && !anchors_.armed(slot)) anchors_.arm(slot, x, c, s);
      }
    }
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
    bool trapped = false;
    if constexpr (kTrap) trapped = trap_.active() && trap_.decides_alone(x, c);
    if constexpr (M.anchors)
      if (anchors_.active() && !trapped) anchors_.arm(slot, x, c, s);
    if constexpr (M.recur)
      if (recur_.active() && !trapped) recur_.arm(slot, x, c, s);
    if constexpr (kTrap)
      if (trap_.active()) trap_.arm(slot, x, c, s);
    if constexpr (M.strobe)
      if (strobe_.active()) strobe_.arm(slot, x, c, s);
  }

  [[gnu::always_inline]] void disarm(int slot) {
    each([&](auto& m) { m.disarm(slot); });
  }

  // Whether a lane flag can be raised now (else the runner's screen loop skips flag()).
  bool flagging() const {
    if constexpr (kTrap) return trap_.active() && trap_.armed_lanes() > 0;
    return false;
  }

  // Before the screen loop that calls flag(): what a mapper computes for the whole tile at once.
  template <class Tile>
  void prepare_flags(const Tile& t) {
    if constexpr (kTrap)
      if (trap_.active()) trap_.prepare_flags(t);
  }

  // The lane flags of the mappers that screen with one (inside the runner's screen loop)…
  template <class Tile>
  [[gnu::always_inline]] LookInt flag(const Tile& t, int i) const {
    LookInt f = 0;
    if constexpr (kTrap)
      if (trap_.active()) f |= trap_.flag(t, i);
    return f;
  }

  // … then the screens of those that make a pass of their own.
  template <class Tile>
  void screen(const Tile& t, LookInt* attention) {
    if constexpr (M.anchors)
      if (anchors_.active()) anchors_.screen(t, attention);
    if constexpr (M.recur)
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

  // Called where the plan asks for the energy trap (its trap_verdict column); a K without one
  // has none compiled in, and its verdict is an inactive trap's.
  TrapVerdict trap_verdict(const Params& c) const {
    if constexpr (kTrap) return trap_.verdict(c);
    return TrapVerdict::not_applicable;
  }

  // The lane's record for the attractor table and why it is undecided (Recurrences::record).
  void recurrence_record(int slot, bool failed, const Settlement<N>& s, double* out,
                         UndecidedReason& why) const {
    if constexpr (M.recur) recur_.record(slot, failed, s, out, why);
  }

 private:
  static bool mapping(const RunPlan& plan) { return plan.map.basin >= 0; }

  // The plan's mappers, which this set must hold: a kernel built for another plan is a bug.
  static MapperChoice used(const RunPlan& plan) {
    MapperChoice u = mappers_of(plan);
    if (!covers(M, u))
      throw std::logic_error("the kernel was compiled without a basin mapper this run uses");
    u.trap = u.trap && energy_trap_at_run_time<S>();  // else the trap would not activate (EnergyTrap)
    return u;
  }

  // The clock of the mappers that sample the stroboscopic map: an adaptive lane's samples are
  // counted, k at t_start + k·period (RunPlan's dense_strobe); else the steps' own.
  static LaneClock map_clock(const RunPlan& plan, LaneClock steps) {
    if (!mapping(plan) || !plan.attractors.dense_strobe) return steps;
    return LaneClock{plan.spec.t_start, *plan.spec.measures.basin->period};
  }

  // Whether mapper m samples the stroboscopic map (when there is one).
  template <class Mapper>
  static constexpr bool samples_map(const Mapper&) {
    return std::is_same_v<Mapper, StroboscopicCycles<D, W>> ||
           std::is_same_v<Mapper, Recurrences<D, W>>;
  }

  // Mapper m looks at the lane at step (or sample) n, unless it has settled. A settlement
  // another mapper refuses (it knows the point is no attractor) is undone, and m stops looking.
  template <class Mapper, class Lane>
  [[gnu::always_inline]] void settle_with(Mapper& m, int slot, std::int64_t n, const Lane& x,
                                          const Params& c, Settlement<N>& s) {
    if (s.settled) return;
    m.look(slot, n, x, c, s);
    // The trap settles at a well's minimum, which no mapper refuses: asking cost the double
    // well's map 2 % of its bookkeeping.
    constexpr bool the_trap = std::is_same_v<Mapper, EnergyTrap<S, Uniform, W>>;
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

  // The active mappers, in order (an absent one is never called, so f is not instantiated for it).
  template <class F>
  [[gnu::always_inline]] void each(F&& f) {
    if constexpr (M.anchors) if (anchors_.active()) f(anchors_);
    if constexpr (kTrap) if (trap_.active()) f(trap_);
    if constexpr (M.strobe) if (strobe_.active()) f(strobe_);
    if constexpr (M.recur) if (recur_.active()) f(recur_);
  }
  template <class F>
  [[gnu::always_inline]] void each(F&& f) const {
    if constexpr (M.anchors) if (anchors_.active()) f(anchors_);
    if constexpr (kTrap) if (trap_.active()) f(trap_);
    if constexpr (M.strobe) if (strobe_.active()) f(strobe_);
    if constexpr (M.recur) if (recur_.active()) f(recur_);
  }

  Anchors anchors_;
  Trap trap_;
  Strobe strobe_;
  Recur recur_;
  bool dense_strobe_;
};

}  // namespace cs
