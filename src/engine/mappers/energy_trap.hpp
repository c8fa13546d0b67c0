// The energy trap (a basin mapper, basin_mapper.hpp) of a scene K = Σp²/2 + V(q) + k·z with
// k < 0 and no time (physics/energy_wells.hpp): E = K(q, p, 0) never rises, so a lane inside the
// wells' box with E below the trap level can never leave its well; it settles at the well's
// minimum, exactly, as soon as a look sees it there. The screen evaluates E through the scene's
// own K, which vectorises like the step.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "engine/attractor_search.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "engine/mappers/energy_trap_record.hpp"
#include "physics/energy_wells.hpp"
#include "physics/partials.hpp"

namespace cs {

template <Scene S, bool Uniform, int W>
class EnergyTrap {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D;
  static constexpr std::int64_t kMostCombinations = kEnergyTrapMostCombinations;
  using Params = ParamsOf<S, double>;
  // A proxy scene (engine/proxy_scene.hpp) answers for a K its step kernel holds: E over a whole
  // tile (tile_energy), the wells (energy_wells.hpp's trap_ functions) and its identity.
  static constexpr bool kProxy = requires { S::identity(); };

 public:
  // Cold, as wells_for(): once per run (BlockRunner::load says why).
  [[gnu::cold]] EnergyTrap(const RunPlan& plan, bool active, LaneClock clock, const Params& uniform)
      : active_(active && energy_trap_at_run_time<S>()),
        clock_(clock),
        tolerance_(plan.attractors.tolerance),
        uniform_params_(uniform) {
    std::fill(well_energy_, well_energy_ + W, -std::numeric_limits<double>::infinity());
    if (!active_) return;
    for (int d = 0; d < D; ++d) angle_period_[d] = plan.attractors.angle_period[static_cast<std::size_t>(d)];
    std::int64_t combinations = 1;
    for (int d = 0; d < D; ++d) {
      q_values_[d] = values_of(plan, d);
      // The map's positions (BasinBox): the spec's q with its axis's values.
      double lo = plan.spec.initial.at(plan.scene.variables[static_cast<std::size_t>(d)].name), hi = lo;
      for (double v : q_values_[d]) lo = std::min(lo, v), hi = std::max(hi, v);
      positions_.lo[d] = lo, positions_.hi[d] = hi;
      widen_[d] = 0.5 * std::max(hi - lo, 1.0);
      // E₀'s kinetic part: the sum of each p's largest p²/2.
      double most = 0.0;
      for (double p : values_of(plan, D + d)) most = std::max(most, 0.5 * (p * p));
      kinetic_ += most;
      if (!q_unbounded_) combinations *= static_cast<std::int64_t>(q_values_[d].size());
      q_unbounded_ = combinations > kMostCombinations;
    }
    if constexpr (Uniform) {
      uniform_wells_ = &wells_for(uniform);
      uniform_box_ = uniform_wells_->box;
    }
  }

  // Not copied: q_values_ may point into fixed_.
  EnergyTrap(const EnergyTrap&) = delete;
  EnergyTrap& operator=(const EnergyTrap&) = delete;

  bool active() const { return active_; }

  void clear(int slot) {
    if (slot >= W) return;
    set_level(slot, -std::numeric_limits<double>::infinity());
    if constexpr (!Uniform)
      for (int d = 0; d < D; ++d) box_lo_[d][slot] = box_hi_[d][slot] = 0.0;
  }

  // Settles a lane whose energy has fallen below its trap level, at its well's minimum.
  template <class Lane>
  void look(int slot, std::int64_t, const Lane& x, const Params& c, Settlement<N>& s) {
    if constexpr (has_energy_trap<S>()) {
      const Wells<D>& wells = wells_of(c);
      for (int d = 0; d < D; ++d)
        if (!(x.q[d] >= wells.box.lo[d] && x.q[d] <= wells.box.hi[d])) return;
      if (!(K<S>(x.q, x.p, 0.0, c, 0.0) < wells.trap_energy)) return;
      std::array<double, D> bottom;
      if (!well_bottom<S>(c, wells.box, clock_.h, x.q, wells, bottom)) {  // a well missed at set-up: the lane is another mapper's now (take_lost)
        lost_ = true;
        disarm(slot);
        return;
      }
      s.settled = true;
      s.period = 1;
      for (int d = 0; d < D; ++d) s.point[d] = bottom[d], s.point[D + d] = 0.0;
      s.settle_time = x.t;  // clock_.at(n), or an adaptive lane's own time
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
    set_level(slot, wells.trap_energy);
    if constexpr (!Uniform)
      for (int d = 0; d < D; ++d) box_lo_[d][slot] = wells.box.lo[d], box_hi_[d][slot] = wells.box.hi[d];
  }

  void disarm(int slot) {
    if (slot < W) set_level(slot, -std::numeric_limits<double>::infinity());
  }

  // Main lanes whose level some E can fall below (flag() can raise theirs).
  int armed_lanes() const { return armed_lanes_; }

  // Before a screen that calls flag(): a proxy scene's E for the whole tile, in one call to its
  // step kernel, which evaluates K over the lanes as the loop below does (a call per lane in
  // the screen loop stopped it vectorising: the double well's map ran 2x slower).
  template <class Tile>
  void prepare_flags(const Tile& t) {
    if constexpr (kProxy) S::tile_energy(t, Uniform ? &uniform_params_ : nullptr, screen_energy_);
  }

  // E = K(q, p, 0) below the lane's trap level, inside the box; branch-free, one lane of the
  // runner's own screen loop (a lane flag: basin_mapper.hpp), so that the tile is read once.
  template <class Tile>
  [[gnu::always_inline]] LookInt flag(const Tile& t, int i) const {
    if constexpr (!has_energy_trap<S>()) return 0;
    else {
      double q[D], p[D];
      LookInt inside = 1;
      for (int d = 0; d < D; ++d) {
        q[d] = t.q[d][i], p[d] = t.p[d][i];
        if constexpr (Uniform) inside &= (q[d] >= uniform_box_.lo[d]) & (q[d] <= uniform_box_.hi[d]);
        else inside &= (q[d] >= box_lo_[d][i]) & (q[d] <= box_hi_[d][i]);
      }
      double energy;
      if constexpr (kProxy)
        energy = screen_energy_[i];  // prepare_flags
      else if constexpr (Uniform)
        energy = K<S>(q, p, 0.0, uniform_params_, 0.0);
      else
        energy = K<S>(q, p, 0.0, t.params(i), 0.0);
      return inside & (energy < well_energy_[i]);
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
  // The values a state variable (q.., p..) takes over the grid: its axis's (the plan's own, not
  // a copy: a 1-D plane's axis is the whole grid), else the spec's one, kept in fixed_.
  std::span<const double> values_of(const RunPlan& plan, int variable) {
    const std::string& name = plan.scene.variables[static_cast<std::size_t>(variable)].name;
    for (const auto& axis : plan.spec.axes)
      if (!axis.is_parameter && !axis.is_step_size && axis.target == name) return axis.values;
    fixed_[variable] = plan.spec.initial.at(name);
    return {&fixed_[variable], 1};
  }

  // The largest initial energy E₀ = K(q₀, p₀, 0) = Σp₀²/2 + V(q₀) of the lanes with parameters
  // c. The grid is a product of axes, so those lanes start at every combination of the state
  // axes' values: E₀ is a function of c and the spec alone (the same on every rank and thread).
  // Its kinetic part is the sum of each p's largest p²/2; V is taken at every combination of
  // the q axes' values, up to kMostCombinations of them (more: +∞, the box is not grown).
  double largest_initial_energy(const Params& c) const {
    if constexpr (!has_energy_trap<S>()) return INFINITY;
    if (q_unbounded_) return INFINITY;
    double potential_max = -INFINITY;
    std::array<std::size_t, D> index{};
    while (true) {
      double q[D];
      for (int d = 0; d < D; ++d) q[d] = q_values_[d][index[d]];
      double v = INFINITY;
      if constexpr (has_energy_trap<S>()) v = trap_potential<S>(q, c);
      if (!(v <= potential_max)) potential_max = std::isnan(v) ? INFINITY : v;
      int d = 0;
      while (d < D && ++index[d] == q_values_[d].size()) index[d++] = 0;
      if (d == D) break;
    }
    return kinetic_ + potential_max;
  }

  void set_level(int slot, double level) {
    const auto armed = [](double e) { return e > -std::numeric_limits<double>::infinity(); };
    armed_lanes_ += int{armed(level)} - int{armed(well_energy_[slot])};
    well_energy_[slot] = level;
  }

  // Per lane parameters: the wells of each parameter set this trap has met, kept here (a runner's
  // own, so no lock): wells_for() computes E₀ and takes the process-wide lock once per set, not
  // once per look (E₀ visits every combination of the q axes' values).
  const Wells<D>& wells_of(const Params& c) const {
    if constexpr (Uniform) return *uniform_wells_;
    else {
      // Neighbouring lanes mostly share their parameters: the last set met is tried first.
      if (last_ < seen_.size() && std::memcmp(&seen_[last_].first, &c, sizeof c) == 0)
        return *seen_[last_].second;
      for (last_ = 0; last_ < seen_.size(); ++last_)
        if (std::memcmp(&seen_[last_].first, &c, sizeof c) == 0) return *seen_[last_].second;
      seen_.emplace_back(c, &wells_for(c));
      return *seen_.back().second;
    }
  }

  // The wells of one parameter set, in the box confining_box() and find_wells() chose for it,
  // found once per process and kept (~0.1 s for the magnetic pendulum; the same bits whichever
  // thread finds them). Entries are never removed, so the references handed out stay valid; a
  // grid has few distinct parameter sets. The box depends on c, the positions, h and E₀ alone,
  // and E₀ on c, the kinetic part and the q axes' values (none when their combinations are too
  // many: E₀ is then +∞): those are the key, and E₀ is computed once per entry (it visits
  // every combination of the q axes' values; per block it cost seconds on a 512² map). The
  // entries of one grid (a parameter axis: one entry per value) share one copy of its q values.
  [[gnu::cold]] const Wells<D>& wells_for(const Params& c) const {
    using Values = std::shared_ptr<const std::vector<double>>;
    struct Known {
      Params params;
      BasinBox<D> positions;
      std::array<double, D> widen;
      double kinetic;
      bool q_unbounded;
      Values q_values[D];  // null when q_unbounded
      double h;
      Wells<D> wells;
      const void* scene;  // scene_identity
    };
    auto same = [](const Values& a, std::span<const double> b) {
      return a && a->size() == b.size() && std::memcmp(a->data(), b.data(), b.size() * sizeof(double)) == 0;
    };
    static std::mutex mutex;
    static std::deque<Known> known;
    std::lock_guard lock(mutex);
    for (const Known& k : known) {
      bool hit = k.scene == scene_identity() && std::memcmp(&k.params, &c, sizeof c) == 0 &&
                 k.positions.lo == positions_.lo &&
                 k.positions.hi == positions_.hi && k.widen == widen_ && k.h == clock_.h &&
                 std::memcmp(&k.kinetic, &kinetic_, sizeof kinetic_) == 0 &&
                 k.q_unbounded == q_unbounded_;
      for (int d = 0; d < D && hit && !q_unbounded_; ++d) hit = same(k.q_values[d], q_values_[d]);
      if (hit) return k.wells;
    }
    const double e0 = largest_initial_energy(c);
    const BasinBox<D> box = trap_box<S>(c, positions_, widen_, e0, clock_.h);
    Known k{c,  positions_, widen_, kinetic_, q_unbounded_, {}, clock_.h,
            trap_wells<S>(c, box, clock_.h), scene_identity()};
    for (int d = 0; d < D && !q_unbounded_; ++d) {
      for (const Known& other : known)
        if (same(other.q_values[d], q_values_[d])) {
          k.q_values[d] = other.q_values[d];
          break;
        }
      if (!k.q_values[d])
        k.q_values[d] = std::make_shared<const std::vector<double>>(q_values_[d].begin(), q_values_[d].end());
    }
    return known.emplace_back(std::move(k)).wells;
  }

  // Which K the wells are of: a proxy scene stands for every K of a step kernel, loaded for the
  // process's life (so a table's address names its K); a compiled scene for its own alone.
  static const void* scene_identity() {
    if constexpr (kProxy) return S::identity();
    else return nullptr;
  }

  bool active_;
  bool lost_ = false;  // see take_lost
  LaneClock clock_;
  double tolerance_;  // the anchor test's (refuses)
  double angle_period_[D] = {};
  Params uniform_params_;
  BasinBox<D> positions_{};        // each q's range over the grid
  std::array<double, D> widen_{};  // … and how far the box extends beyond it (BasinBox)
  // Each q's values over the grid (the plan's axis, or fixed_), and whether their combinations
  // are more than E₀ visits (largest_initial_energy).
  std::span<const double> q_values_[D];
  bool q_unbounded_ = false;
  double kinetic_ = 0.0;  // E₀'s kinetic part: Σ over p of its largest p²/2 over the grid
  double fixed_[N] = {};  // the spec's value of a variable without an axis (values_of)
  mutable std::vector<std::pair<Params, const Wells<D>*>> seen_;  // wells_of (not Uniform)
  mutable std::size_t last_ = 0;  // … the one met last
  const Wells<D>* uniform_wells_ = nullptr;  // Uniform: the one parameter set's
  BasinBox<D> uniform_box_{};                // … and their box, read by the screen
  alignas(64) double well_energy_[W];    // the lane's trap level (−∞: none; set_level)
  // A proxy scene's E of each lane, for the screen (prepare_flags); else unused.
  alignas(64) double screen_energy_[kProxy ? W : 1];
  int armed_lanes_ = 0;                  // … how many are above −∞
  alignas(64) double box_lo_[Uniform ? 1 : D][W];  // the lane's wells' box (not Uniform)
  alignas(64) double box_hi_[Uniform ? 1 : D][W];
};

}  // namespace cs
