// The energy trap (a basin mapper, basin_mapper.hpp) of a scene K = Σp²/2 + V(q) + k·z with
// k < 0 and no time (physics/energy_wells.hpp): E = K(q, p, 0) never rises, so a lane inside the
// wells' box with E below the trap level can never leave its well; it settles at the well's
// minimum, exactly, as soon as a look sees it there. The screen evaluates E through the scene's
// own K, which vectorises like the step.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <limits>
#include <mutex>
#include <utility>

#include "engine/attractor_search.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "physics/energy_wells.hpp"
#include "physics/partials.hpp"

namespace cs {

template <Scene S, bool Uniform, int W>
class EnergyTrap {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D;
  using Params = ParamsOf<S, double>;

 public:
  EnergyTrap(const RunPlan& plan, bool active, LaneClock clock, const Params& uniform)
      : active_(active && has_energy_trap<S>()),
        clock_(clock),
        tolerance_(plan.attractors.tolerance),
        uniform_params_(uniform) {
    if (!active_) return;
    for (int d = 0; d < D; ++d) angle_period_[d] = plan.attractors.angle_period[static_cast<std::size_t>(d)];
    grid_box_ = basin_box(plan);
    if constexpr (Uniform) {
      uniform_wells_ = &wells_for(uniform);
      uniform_box_ = uniform_wells_->box;
    }
  }

  bool active() const { return active_; }

  void clear(int slot) {
    if (slot >= W) return;
    well_energy_[slot] = -std::numeric_limits<double>::infinity();
    if constexpr (!Uniform)
      for (int d = 0; d < D; ++d) box_lo_[d][slot] = box_hi_[d][slot] = 0.0;
  }

  // Settles a lane whose energy has fallen below its trap level, at its well's minimum.
  template <class Lane>
  void look(int slot, std::int64_t n, const Lane& x, const Params& c, Settlement<N>& s) {
    if constexpr (has_energy_trap<S>()) {
      const Wells<D>& wells = wells_of(c);
      for (int d = 0; d < D; ++d)
        if (!(x.q[d] >= wells.box.lo[d] && x.q[d] <= wells.box.hi[d])) return;
      if (!(K<S>(x.q, x.p, 0.0, c, 0.0) < wells.trap_energy)) return;
      const auto bottom = WellFinder<S>(c, wells.box, clock_.h).bottom(x.q, wells);
      if (!bottom) {  // a well missed at set-up: the lane is another mapper's now (take_lost)
        lost_ = true;
        disarm(slot);
        return;
      }
      s.settled = true;
      s.period = 1;
      for (int d = 0; d < D; ++d) s.point[d] = (*bottom)[d], s.point[D + d] = 0.0;
      s.settle_time = clock_.at(n);
    }
  }

  // Whether the trap alone decides a lane that starts at x: served, every well it knows traps
  // (its minimum below the level), and E too low ever to reach the box's boundary. E never
  // rises, so the lane ends trapped, or on a saddle or maximum (refuses) where it stays
  // undecided, or in a well missed at set-up (handed over: take_lost).
  template <class Lane>
  bool decides_alone(const Lane& x, const Params& c) const {
    if constexpr (!has_energy_trap<S>()) return false;
    else {
      const Wells<D>& wells = wells_of(c);
      return wells.usable && wells.highest_minimum < wells.trap_energy &&
             K<S>(x.q, x.p, 0.0, c, 0.0) < wells.confinement;
    }
  }

  // Whether the last look found the lane below the level in a well it does not know; clears.
  bool take_lost() { return std::exchange(lost_, false); }

  template <class Lane>
  void arm(int slot, const Lane&, const Params& c, const Settlement<N>&) {
    const Wells<D>& wells = wells_of(c);
    well_energy_[slot] = wells.trap_energy;
    if constexpr (!Uniform)
      for (int d = 0; d < D; ++d) box_lo_[d][slot] = wells.box.lo[d], box_hi_[d][slot] = wells.box.hi[d];
  }

  void disarm(int slot) {
    if (slot < W) well_energy_[slot] = -std::numeric_limits<double>::infinity();
  }

  // E = K(q, p, 0) below the lane's trap level, inside the box; branch-free.
  template <class Tile>
  void screen(const Tile& t, LookInt* attention) {
    if constexpr (has_energy_trap<S>()) {
#pragma GCC ivdep
      for (int i = 0; i < W; ++i) {
        double q[D], p[D];
        LookInt inside = 1;
        for (int d = 0; d < D; ++d) {
          q[d] = t.q[d][i], p[d] = t.p[d][i];
          if constexpr (Uniform) inside &= (q[d] >= uniform_box_.lo[d]) & (q[d] <= uniform_box_.hi[d]);
          else inside &= (q[d] >= box_lo_[d][i]) & (q[d] <= box_hi_[d][i]);
        }
        double energy;
        if constexpr (Uniform) energy = K<S>(q, p, 0.0, uniform_params_, 0.0);
        else energy = K<S>(q, p, 0.0, t.params(i), 0.0);
        attention[i] |= inside & (energy < well_energy_[i]);
      }
    }
  }

  // Another mapper's fixed point on a saddle or maximum of V, where the trap serves the lane, is
  // no attractor: a lane that starts exactly on an unstable equilibrium stays there, undecided
  // (as the double well's saddle (0, 0) always was).
  bool refuses(const Settlement<N>& s, const Params& c) const {
    if (!has_energy_trap<S>() || s.period != 1) return false;
    const Wells<D>& wells = wells_of(c);
    if (wells.verdict != TrapVerdict::used) return false;
    for (int d = 0; d < D; ++d)
      if (!(std::fabs(s.point[D + d]) <= tolerance_)) return false;
    for (const auto& u : wells.unstable) {
      bool near = true;
      for (int d = 0; d < D; ++d)
        near = near && std::fabs(phase_difference(s.point[d], u[d], angle_period_[d])) <= tolerance_;
      if (near) return true;
    }
    return false;
  }

  void move(int, int) {}
  std::int64_t next_look(std::int64_t) const { return std::numeric_limits<std::int64_t>::max(); }

  // Whether the trap served a lane of these parameters, and if not why (the `energy_trap`
  // attribute, parallel/basin_summary.cpp).
  TrapVerdict verdict(const Params& c) const {
    return active_ ? wells_of(c).verdict : TrapVerdict::not_applicable;
  }

 private:
  // The box the map's positions lie in (BasinBox): each q's range over the grid, widened.
  static BasinBox<D> basin_box(const RunPlan& plan) {
    BasinBox<D> box;
    for (int d = 0; d < D; ++d) {
      const std::string& name = plan.scene.variables[static_cast<std::size_t>(d)].name;
      double lo = plan.spec.initial.at(name), hi = lo;
      for (const auto& axis : plan.spec.axes)
        if (!axis.is_parameter && !axis.is_step_size && axis.target == name)
          for (double v : axis.values) lo = std::min(lo, v), hi = std::max(hi, v);
      const double widen = 0.5 * std::max(hi - lo, 1.0);
      box.lo[d] = lo - widen, box.hi[d] = hi + widen;
    }
    return box;
  }

  const Wells<D>& wells_of(const Params& c) const {
    if constexpr (Uniform) return *uniform_wells_;
    else return wells_for(c);
  }

  // The wells of one parameter set, in the box find_wells() chose for it, found once per process
  // and kept (~0.1 s for the magnetic pendulum; the same bits whichever thread finds them).
  // Entries are never removed, so the references handed out stay valid; a grid has few
  // distinct parameter sets.
  const Wells<D>& wells_for(const Params& c) const {
    struct Known {
      Params params;
      BasinBox<D> box;
      double h;
      Wells<D> wells;
    };
    static std::mutex mutex;
    static std::deque<Known> known;
    std::lock_guard lock(mutex);
    for (const Known& k : known)
      if (std::memcmp(&k.params, &c, sizeof c) == 0 && k.box.lo == grid_box_.lo &&
          k.box.hi == grid_box_.hi && k.h == clock_.h)
        return k.wells;
    known.push_back({c, grid_box_, clock_.h, find_wells<S>(c, grid_box_, clock_.h)});
    return known.back().wells;
  }

  bool active_;
  bool lost_ = false;  // see take_lost
  LaneClock clock_;
  double tolerance_;  // the anchor test's (refuses)
  double angle_period_[D] = {};
  Params uniform_params_;
  BasinBox<D> grid_box_{};                // the map's positions, widened (basin_box)
  const Wells<D>* uniform_wells_ = nullptr;  // Uniform: the one parameter set's
  BasinBox<D> uniform_box_{};                // … and their box, read by the screen
  alignas(64) double well_energy_[W];    // the lane's trap level (−∞: none)
  alignas(64) double box_lo_[Uniform ? 1 : D][W];  // the lane's wells' box (not Uniform)
  alignas(64) double box_hi_[Uniform ? 1 : D][W];
};

}  // namespace cs
