// Integrates a contiguous range of grid points with one scene × method × carried-state
// instantiation. Lanes are grid points; a tile of W lanes is advanced `chunk` steps at a time,
// then looked at: lanes that finished (t_end reached, basin decided with early stop, diverged,
// broke down) hand their results over and their slot is refilled with the next point, so lanes
// that stop early stop costing time. A lane's arithmetic never depends on its slot or on the
// other lanes, so results are the same bits for any split of the grid over ranks and threads.
//
// Every lane has done a multiple of `chunk` steps when looked at, except for the last
// steps % chunk steps: lanes that reach that remainder move to a second "finisher" tile, which
// runs them in one go once it is full (or at the end of the block).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>

#include "engine/attractor_search.hpp"
#include "engine/lane_tile.hpp"
#include "engine/run_plan.hpp"
#include "engine/sync_tracker.hpp"
#include "physics/double_well.hpp"
#include "physics/energy_wells.hpp"
#include "physics/partials.hpp"
#include "physics/scene_bounds.hpp"

namespace cs {

// The integer type of the looks' per-lane flags and countdowns (BlockRunner::screen()). With
// AVX2 they are as wide as the doubles they come from, so the vector loop packs no 64-bit compare
// masks into 32-bit lanes: the looks' share of the 512² basin map went from 6.8 to 5.7 % (Zen 4,
// perf). AVX-512 compares into mask registers, which pack for free; there 64-bit flags only
// double the arrays (7.2–8.1 % against 6.7–7.3 %, four runs each). Only speed depends on it.
#ifdef __AVX512F__
using LookInt = std::int32_t;
#else
using LookInt = std::int64_t;
#endif

template <Scene S, class Method, Carry carry, bool Uniform>
class BlockRunner {
  static constexpr int W = 64;
  static constexpr int D = S::dof;
  static constexpr int kMaxVars = 2 * D + 2;  // q.., p.., z, lambda
  static constexpr int N = 2 * D;             // phase space: q.., p..
  static constexpr int kParamSlots = sizeof(ParamsOf<S, double>) / sizeof(double);
  using Tile = LaneTile<S, Method, W>;
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;

  // Per-slot bookkeeping that travels with a lane from one tile to the other.
  struct Book {
    std::int64_t point = -1;  // −1: empty slot
    std::int64_t n = 0;       // steps done
    bool trapped = false;     // basin decided by the energy trap
    bool settled = false;     // attractor found (BasinMode::found)
    bool non_finite = false;  // a trajectory sample written was not finite
    int period = 0;           // of the cycle it settled on
    std::array<double, N> attractor{};
    // Its stroboscopic samples (a forced scene's period), kept beside the books: a tracker is
    // ~1 KB, and copying it with every book made the double well's map 8 % slower.
    CycleTracker<N>* cycle = nullptr;
    double settle_time = 0.0;
    std::int64_t samples_recorded = 0;  // trajectory samples 0 … samples_recorded − 1 written
    SyncTracker sync;
  };

 public:
  BlockRunner(const RunPlan& plan, BlockResults& out) : plan_(plan), out_(out) {
    const auto& base = plan.grid.base_parameters();
    uniform_params_ = S::params_from(base.data());
    t_start_ = plan.spec.t_start;
    h_ = plan.spec.h;
    LaneState<D> x{};
    x.t = t_start_;
    uniform_coef_ = Method::template coefficients<S>(plan.spec.h, uniform_params_, x);
    steps_ = plan.spec.steps;
    remainder_ = static_cast<int>(steps_ % plan.chunk);
    const auto& m = plan.spec.measures;
    sync_n0_ = plan.sync_first_step;
    sync_n1_ = plan.sync_last_step;
    if (m.basin) basin_early_stop_ = m.basin->early_stop;
    const bool found = plan.basin_mode == BasinMode::found;
    strobe_ = found && m.basin->period.has_value();
    look_search_ = found && !strobe_;
    if (strobe_) {
      main_cycles_ = std::make_unique<CycleTracker<N>[]>(W);
      fin_cycles_ = std::make_unique<CycleTracker<N>[]>(W);
    }
    energy_search_ = found && has_energy_trap<S>() && m.basin->exact_trap;
    if (energy_search_) {
      grid_box_ = basin_box();
      if constexpr (Uniform) box_ = wells_for(uniform_params_).box;
    }
    for (int k = 0; k < N && found; ++k) {
      angle_period_[k] = plan.attractors.angle_period[static_cast<std::size_t>(k)];
      angle_frequency_[k] = angle_period_[k] > 0.0 ? 1.0 / angle_period_[k] : 0.0;
    }
    idle_ = make_idle_lane();
  }

  void run() {
    next_ = out_.range.begin;
    for (int i = 0; i < W; ++i) clear(main_, main_book_, i);
    for (int i = 0; i < W; ++i) clear(fin_, fin_book_, i);
    refill();
    std::int64_t reported = 0;  // lane-steps added to the progress counter
    while (active_ > 0 || fin_count_ > 0) {
      if (active_ > 0) {
        advance_tile(main_, plan_.chunk);
        if (out_.in_flight_steps != nullptr) {
          const std::int64_t steps = std::int64_t{active_} * plan_.chunk;
          out_.in_flight_steps->fetch_add(steps, std::memory_order_relaxed);
          reported += steps;
        }
        look_at_main();
        refill();
      }
      if (fin_count_ == W || (active_ == 0 && fin_count_ > 0)) run_finisher();
    }
    if (out_.in_flight_steps != nullptr)
      out_.in_flight_steps->fetch_sub(reported, std::memory_order_relaxed);
  }

 private:
  // ---- lanes in and out ----------------------------------------------------------------------

  LaneState<D> make_idle_lane() const {
    LaneState<D> x{};
    double params[kParamSlots], state[kMaxVars];
    plan_.grid.point(out_.range.begin - plan_.point_offset, params, state);
    load_state(x, state);
    x.t = t_start_;
    Params c = S::params_from(params);
    Method::template start<S>(x, c);
    return x;
  }

  // A lane's time after n steps, computed as the kernel does (lane_tile.hpp).
  double time_at(std::int64_t n) const { return t_start_ + static_cast<double>(n) * h_; }

  static void load_state(LaneState<D>& x, const double* state) {
    for (int d = 0; d < D; ++d) x.q[d] = state[d], x.p[d] = state[D + d];
    x.z = state[2 * D];
    x.mu = std::log(state[2 * D + 1]);
    x.lambda_numerator = x.lambda_denominator = 1.0;
    x.lambda_folds = 0.0;
    x.broken = 0.0;
  }

  void clear(Tile& t, Book* book, int i) {
    t.set_lane(i, idle_);
    t.set_parameters(i, uniform_params_, uniform_coef_);
    book[i] = Book{};
    t.steps_done[i] = 0.0;
    if (&t == &main_) {
      steps_done_[i] = 0;
      countdown_[i] = std::numeric_limits<LookInt>::max();
      trap_energy_[i] = -std::numeric_limits<double>::infinity();
      a2_[i] = 0.0;
      near_[i] = 0.0;
      well_energy_[i] = -std::numeric_limits<double>::infinity();
      dwell_needed_[i] = std::numeric_limits<double>::infinity();
      for (int k = 0; k < N; ++k) anchor_[k][i] = 0.0;
      if constexpr (!Uniform)
        for (int d = 0; d < D; ++d) box_lo_[d][i] = box_hi_[d][i] = 0.0;
    }
  }

  // Double well: E = p²/2 + U(q) never increases for γ ≥ 0, so once E < U(0) = a⁴/2 (less a
  // margin for the integrator's energy error) the lane can never cross q = 0 again.
  // The margin covers the integrator's energy oscillation, which scales like E·(hω)² with
  // E ~ a⁴ and ω ~ a: margin = C·h²·a⁶ (C in the plan, measured in the basin tests).
  double trap_energy(const Params& c) const {
    if constexpr (std::is_same_v<S, DoubleWell>) {
      if (plan_.basin_mode == BasinMode::trap && c.gamma >= 0.0) {
        double a2 = c.a * c.a, h = plan_.spec.h;
        return 0.5 * a2 * a2 - plan_.basin_margin_coefficient * (h * h) * (a2 * a2 * a2);
      }
    }
    return -std::numeric_limits<double>::infinity();
  }

  void arm_trap(int i, const Params& c) {
    if constexpr (std::is_same_v<S, DoubleWell>) {
      a2_[i] = c.a * c.a;
      trap_energy_[i] = trap_energy(c);
    }
  }

  void refill() {
    if (active_ == W) return;  // the common case; scanning 64 books a chunk cost 6 % of a map
    for (int i = 0; i < W && next_ < out_.range.end; ++i) {
      if (main_book_[i].point >= 0) continue;
      while (next_ < out_.range.end && !load(i, next_++)) {
      }
    }
  }

  // Puts point `k` into main slot i; false when it is finished at once (breakdown at t = 0).
  bool load(int i, std::int64_t k) {
    double params[kParamSlots], state[kMaxVars];
    plan_.grid.point(k - plan_.point_offset, params, state);
    LaneState<D> x{};
    load_state(x, state);
    x.t = t_start_;
    Params c = S::params_from(params);
    Method::template start<S>(x, c);
    Coef coef = Method::template coefficients<S>(plan_.spec.h, c, x);
    Book b;
    b.point = k;
    if (strobe_) {
      main_cycles_[i] = CycleTracker<N>{};
      b.cycle = &main_cycles_[i];
    }
    if (!defined_at(x, c)) {  // no dynamics to integrate: K or a partial is not finite
      finish(b, x, c, LaneStatus::undefined_at_start);
      return false;
    }
    if (Method::template breaks_down<S>(coef)) {
      observe(b, x, c);  // the initial state is sound; its first step is what breaks down
      finish(b, x, c, LaneStatus::breakdown);
      return false;
    }
    observe(b, x, c);
    if (decided(b) && basin_early_stop_) {  // decided before the first step
      finish(b, x, c, LaneStatus::ok);
      return false;
    }
    main_.set_lane(i, x);
    main_.set_parameters(i, c, coef);
    main_book_[i] = b;
    countdown_[i] = chunks_until_due(0);
    arm_trap(i, c);
    if (b.trapped) trap_energy_[i] = -std::numeric_limits<double>::infinity();
    if (look_search_ && !b.settled) {
      for (int d = 0; d < D; ++d) anchor_[d][i] = x.q[d], anchor_[D + d][i] = x.p[d];
      dwell_needed_[i] = plan_.attractors.dwell_samples;
    }
    if (energy_search_ && !b.settled) {
      const Wells<D>& wells = wells_for(c);
      well_energy_[i] = wells.trap_energy;
      if constexpr (!Uniform)
        for (int d = 0; d < D; ++d) box_lo_[d][i] = wells.box.lo[d], box_hi_[d][i] = wells.box.hi[d];
    }
    ++active_;
    if (steps_ < plan_.chunk) move_to_finisher(i);  // a run shorter than one chunk
    return true;
  }

  // ---- stepping ------------------------------------------------------------------------------

  void advance_tile(Tile& t, int steps) {
    advance<S, Method, carry, Uniform>(t, steps, uniform_params_, uniform_coef_, t_start_, h_,
                                       [](int) {});
  }

  // Which lanes need a closer look after a chunk: failed, trapped in a well, or due for a
  // sample or the end. Branch-free over the tile so that it vectorises like the step.
  void screen() {
    Tile& t = main_;
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LookInt healthy = 1;
      if constexpr (!S::kz_constant) healthy = t.broken[i] <= 0.0;  // else never set
      for (int d = 0; d < D; ++d)
        healthy &= (std::fabs(t.q[d][i]) <= kDivergenceBound) & (std::fabs(t.p[d][i]) <= kDivergenceBound);
      LookInt trapped = 0;
      if constexpr (std::is_same_v<S, DoubleWell>) {
        double well = t.q[0][i] * t.q[0][i] - a2_[i];
        trapped = 0.5 * (t.p[0][i] * t.p[0][i]) + 0.5 * (well * well) < trap_energy_[i];
      }
      countdown_[i] -= 1;
      steps_done_[i] += plan_.chunk;
      if constexpr (time_dependent<S>()) t.steps_done[i] += plan_.chunk;  // read for t alone
      attention_[i] = (!healthy) | trapped | (countdown_[i] <= 0);
    }
    if (look_search_) search_on_looks();
    if (energy_search_) search_energy_trap();
  }

  // E = K(q, p, 0) below the lane's trap level, inside the box (energy_wells.hpp).
  void search_energy_trap() {
    if constexpr (has_energy_trap<S>()) {
      Tile& t = main_;
#pragma GCC ivdep
      for (int i = 0; i < W; ++i) {
        double q[D], p[D];
        LookInt inside = 1;
        for (int d = 0; d < D; ++d) {
          q[d] = t.q[d][i], p[d] = t.p[d][i];
          if constexpr (Uniform) inside &= (q[d] >= box_.lo[d]) & (q[d] <= box_.hi[d]);
          else inside &= (q[d] >= box_lo_[d][i]) & (q[d] <= box_hi_[d][i]);
        }
        double energy;
        if constexpr (Uniform) energy = K<S>(q, p, 0.0, uniform_params_, 0.0);
        else energy = K<S>(q, p, 0.0, t.params(i), 0.0);
        attention_[i] |= inside & (energy < well_energy_[i]);
      }
    }
  }

  // The box the map's positions lie in (BasinBox): each q's range over the grid, widened.
  BasinBox<D> basin_box() const {
    BasinBox<D> box;
    for (int d = 0; d < D; ++d) {
      const std::string& name = plan_.scene.variables[static_cast<std::size_t>(d)].name;
      double lo = plan_.spec.initial.at(name), hi = lo;
      for (const auto& axis : plan_.spec.axes)
        if (!axis.is_parameter && !axis.is_step_size && axis.target == name)
          for (double v : axis.values) lo = std::min(lo, v), hi = std::max(hi, v);
      const double widen = 0.5 * std::max(hi - lo, 1.0);
      box.lo[d] = lo - widen, box.hi[d] = hi + widen;
    }
    return box;
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
          k.box.hi == grid_box_.hi && k.h == h_)
        return k.wells;
    known.push_back({c, grid_box_, h_, find_wells<S>(c, grid_box_, h_)});
    return known.back().wells;
  }

  // Settles a lane whose energy has fallen below its trap level, at its well's minimum.
  void check_energy_trap(Book& b, const LaneState<D>& x, const Params& c) {
    if constexpr (has_energy_trap<S>()) {
      const Wells<D>& wells = wells_for(c);
      for (int d = 0; d < D; ++d)
        if (!(x.q[d] >= wells.box.lo[d] && x.q[d] <= wells.box.hi[d])) return;
      if (!(K<S>(x.q, x.p, 0.0, c, 0.0) < wells.trap_energy)) return;
      const auto bottom = WellFinder<S>(c, wells.box, h_).bottom(x.q, wells);
      if (!bottom) return;
      b.settled = true;
      b.period = 1;
      for (int d = 0; d < D; ++d) b.attractor[d] = (*bottom)[d], b.attractor[D + d] = 0.0;
      b.settle_time = time_at(b.n);
    }
  }

  // Attractors of an autonomous scene, looked for at every look: a lane's run near its anchor
  // (the point where the run began) grows by one look while it stays within the tolerance, and
  // starts again from where the lane is when it does not. Branch-free, like screen().
  void search_on_looks() {
    Tile& t = main_;
    const double tolerance = plan_.attractors.tolerance;
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LookInt near = 1;
      for (int d = 0; d < D; ++d) {
        near &= std::fabs(folded(t.q[d][i] - anchor_[d][i], d)) <= tolerance;
        near &= std::fabs(folded(t.p[d][i] - anchor_[D + d][i], D + d)) <= tolerance;
      }
      near_[i] = near ? near_[i] + 1.0 : 0.0;
      for (int d = 0; d < D; ++d) {
        anchor_[d][i] = near ? anchor_[d][i] : t.q[d][i];
        anchor_[D + d][i] = near ? anchor_[D + d][i] : t.p[d][i];
      }
      attention_[i] |= near_[i] >= dwell_needed_[i];
    }
  }

  // A difference of variable k folded into [−period/2, period/2] if k is an angle (as
  // phase_difference, without a branch: the frequency of a non-angle is 0).
  double folded(double difference, int k) const {
    return difference - angle_period_[k] * std::nearbyint(difference * angle_frequency_[k]);
  }

  // Chunks until a lane at step n is due for a sample or for the end of its run.
  // Clamped to LookInt: a countdown that runs out early only brings one more look, which sets
  // the next countdown.
  LookInt chunks_until_due(std::int64_t n) const {
    std::int64_t due = (steps_ / plan_.chunk) * plan_.chunk;
    if (plan_.samples > 0) {
      auto every = plan_.spec.measures.trajectory->every;
      due = std::min(due, (n / every + 1) * every);
    }
    if (plan_.map.sync_r >= 0 && n < sync_n1_)
      due = std::min(due, n < sync_n0_ ? sync_n0_ : n + plan_.chunk);
    if (strobe_) {
      auto every = plan_.attractors.sample_steps;
      due = std::min(due, (n / every + 1) * every);
    }
    return static_cast<LookInt>(
        std::min<std::int64_t>((due - n) / plan_.chunk, std::numeric_limits<LookInt>::max()));
  }

  void look_at_main() {
    screen();
    LookInt any = 0;
    for (int i = 0; i < W; ++i) any |= attention_[i];
    if (!any) return;  // the common case: nothing to do until the next chunk
    for (int i = 0; i < W; ++i) {
      Book& b = main_book_[i];
      if (!attention_[i] || b.point < 0) continue;
      b.n = steps_done_[i];
      countdown_[i] = chunks_until_due(b.n);
      LaneState<D> x = main_.lane(i);
      x.t = time_at(b.n);
      const Params c = main_.params(i);
      LaneStatus status = LaneStatus::ok;
      bool failed = lane_failed(x, status);
      if (!failed && look_search_ && !b.settled && near_[i] >= dwell_needed_[i]) {
        settle(b, x, 1, b.n - static_cast<std::int64_t>(near_[i]) * plan_.chunk);
        dwell_needed_[i] = std::numeric_limits<double>::infinity();
      }
      if (!failed) observe(b, x, c);
      if (b.settled) {  // nothing more to look for
        dwell_needed_[i] = std::numeric_limits<double>::infinity();
        well_energy_[i] = -std::numeric_limits<double>::infinity();
      }
      bool done = failed || b.n == steps_ || (decided(b) && basin_early_stop_);
      if (b.trapped) trap_energy_[i] = -std::numeric_limits<double>::infinity();
      if (done) {
        finish(b, x, c, status);
        clear(main_, main_book_, i);
        --active_;
      } else if (steps_ - b.n < plan_.chunk) {
        move_to_finisher(i);
      }
    }
  }

  void move_to_finisher(int i) {
    if (fin_count_ == W) run_finisher();
    int j = fin_count_++;
    fin_.set_lane(j, main_.lane(i));
    fin_.set_parameters(j, main_.params(i), main_.coef(i));
    fin_.steps_done[j] = main_.steps_done[i];
    fin_book_[j] = main_book_[i];
    if (strobe_) {
      fin_cycles_[j] = main_cycles_[i];
      fin_book_[j].cycle = &fin_cycles_[j];
    }
    clear(main_, main_book_, i);
    --active_;
  }

  void run_finisher() {
    advance_tile(fin_, remainder_);
    for (int j = 0; j < fin_count_; ++j) {
      Book& b = fin_book_[j];
      b.n += remainder_;
      LaneState<D> x = fin_.lane(j);
      x.t = time_at(b.n);
      LaneStatus status = LaneStatus::ok;
      lane_failed(x, status);
      const Params c = fin_.params(j);
      if (status == LaneStatus::ok) observe(b, x, c);
      finish(b, x, c, status);
      clear(fin_, fin_book_, j);
    }
    fin_count_ = 0;
  }

  // The initial state and K, K_q, K_p, K_z there are finite (Lane–Emden's (2/t)·z at t = 0,
  // log(q) at q < 0 are not).
  static bool defined_at(const LaneState<D>& x, const Params& c) {
    bool finite = std::isfinite(x.z) && std::isfinite(x.mu) &&
                  std::isfinite(K<S>(x.q, x.p, x.z, c, x.t)) &&
                  std::isfinite(K_z<S>(x.q, x.p, x.z, c, x.t));
    for_each_dof<D>([&](auto i) {
      finite = finite && std::isfinite(x.q[i]) && std::isfinite(x.p[i]) &&
               std::isfinite(K_q<S, i>(x.q, x.p, x.z, c, x.t)) &&
               std::isfinite(K_p<S, i>(x.q, x.p, x.z, c, x.t));
    });
    return finite;
  }

  static bool lane_failed(const LaneState<D>& x, LaneStatus& status) {
    if (x.broken > 0.0) status = LaneStatus::breakdown;
    else if (S::diverged(x.q, x.p)) status = LaneStatus::diverged;
    return status != LaneStatus::ok;
  }

  // ---- measures ------------------------------------------------------------------------------

  // Looks at a healthy lane at step b.n (a multiple of the chunk, or t_end).
  void observe(Book& b, const LaneState<D>& x, const Params& c) {
    const auto& map = plan_.map;
    if (map.basin >= 0 && !b.trapped) check_trap(b, x, c);
    if (energy_search_ && !b.settled) check_energy_trap(b, x, c);
    if (strobe_ && !b.settled && b.n % plan_.attractors.sample_steps == 0) {
      typename CycleTracker<N>::Point point;
      for (int d = 0; d < D; ++d) point[d] = x.q[d], point[D + d] = x.p[d];
      if (const int m = b.cycle->feed(point, plan_.attractors)) {
        b.settled = true;
        b.period = m;
        b.attractor = b.cycle->representative(m, plan_.attractors);
        b.settle_time = time_at(b.cycle->settled_start() * plan_.attractors.sample_steps);
      }
    }
    if (plan_.samples > 0) {
      auto every = plan_.spec.measures.trajectory->every;
      if (b.n % every == 0) {
        record_sample(b, b.n / every, x, c);
        b.samples_recorded = b.n / every + 1;
      }
    }
    if (map.sync_r >= 0 && b.n >= sync_n0_ && b.n <= sync_n1_ && b.n % plan_.chunk == 0)
      sample_sync(b, b.n, x.q, x.p, c);
  }

  void sample_sync(Book& b, std::int64_t n, const double* q, const double* p, const Params& c) {
    if constexpr (D >= 2) {
      const auto& sync = *plan_.spec.measures.sync;
      const int i = sync.dof[0], j = sync.dof[1];
      double omega_i = 1.0, omega_j = 1.0;
      if (sync.omega) {
        omega_i = (*sync.omega)[0], omega_j = (*sync.omega)[1];
      } else if constexpr (requires { c.omega1_sq; }) {  // coupled_oscillators: its own
        omega_i = std::sqrt(i == 0 ? c.omega1_sq : c.omega2_sq);
        omega_j = std::sqrt(j == 0 ? c.omega1_sq : c.omega2_sq);
      }
      b.sync.sample(n, sync_n0_, sync_n1_, q[i], p[i], q[j], p[j], omega_i, omega_j);
    }
  }

  static bool decided(const Book& b) { return b.trapped || b.settled; }

  // An autonomous lane settled on the fixed point near x, having stayed near it since step n0.
  void settle(Book& b, const LaneState<D>& x, int period, std::int64_t n0) {
    typename CycleTracker<N>::Point point;
    for (int d = 0; d < D; ++d) point[d] = x.q[d], point[D + d] = x.p[d];
    b.settled = true;
    b.period = period;
    b.attractor = CycleTracker<N>::reduced(point, plan_.attractors);
    b.settle_time = time_at(n0);
  }

  void check_trap(Book& b, const LaneState<D>& x, const Params& c) {
    if constexpr (std::is_same_v<S, DoubleWell>) {
      double well = x.q[0] * x.q[0] - c.a * c.a;
      double energy = 0.5 * (x.p[0] * x.p[0]) + 0.5 * (well * well);  // as in screen()
      if (energy < trap_energy(c)) {
        b.trapped = true;
        b.settle_time = time_at(b.n);
      }
    }
  }

  double* column(int c, std::int64_t point) {
    auto& col = out_.columns[static_cast<std::size_t>(c)];
    auto width = plan_.columns[static_cast<std::size_t>(c)].width;
    return col.data() + (point - out_.range.begin) * width;
  }

  void state_values(const LaneState<D>& x, const Params& c, double* v, double& H) const {
    for (int d = 0; d < D; ++d) v[d] = x.q[d], v[D + d] = x.p[d];
    v[2 * D] = x.z;
    const double log_lambda_now = log_lambda<S>(x);
    v[2 * D + 1] = log_lambda_now;
    // λK in the log domain: late in a damped run λ overflows while K underflows.
    double k = K<S>(x.q, x.p, x.z, c, x.t);
    H = k == 0.0 ? 0.0 : std::copysign(std::exp(log_lambda_now + std::log(std::fabs(k))), k);
  }

  void record_sample(Book& b, std::int64_t sample, const LaneState<D>& x, const Params& c) {
    double v[kMaxVars], H;
    state_values(x, c, v, H);
    const auto& map = plan_.map;
    bool finite = true;
    for (int k = 0; k < kMaxVars; ++k)
      if (map.traj_vars[k] >= 0) {
        column(map.traj_vars[k], b.point)[sample] = v[k];
        finite = finite && std::isfinite(v[k]);
      }
    if (map.traj_H >= 0) {
      column(map.traj_H, b.point)[sample] = H;
      finite = finite && std::isfinite(H);
    }
    if (!finite) b.non_finite = true;
  }

  // Writes a lane's results. A lane that ran (status ok) but wrote a value that is not finite
  // where the dataset promises one (ln λ or H overflowing, z where K is undefined along the
  // path) is flagged non_finite: its values are written as computed, its basin kept (decided on
  // q and p, which are finite), and no cell with a non-finite value reads ok.
  void finish(const Book& b, const LaneState<D>& x, const Params& c, LaneStatus status) {
    const auto& map = plan_.map;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto k = b.point;
    out_.lane_steps += b.n;
    double v[kMaxVars], H;
    state_values(x, c, v, H);
    if (status == LaneStatus::breakdown || status == LaneStatus::undefined_at_start) {
      for (auto& value : v) value = nan;
      H = nan;
    }
    bool finite = !b.non_finite;
    for (int i = 0; i < kMaxVars; ++i)
      if (map.final_vars[i] >= 0) {
        column(map.final_vars[i], k)[0] = v[i];
        finite = finite && std::isfinite(v[i]);
      }
    if (map.final_H >= 0) {
      column(map.final_H, k)[0] = H;
      finite = finite && std::isfinite(H);
    }
    if (map.sync_r >= 0) finite = finish_sync(b, status) && finite;
    if (map.basin >= 0) finish_basin(b, x, status);
    if (map.trap_verdict >= 0) {
      TrapVerdict verdict = TrapVerdict::not_applicable;
      if constexpr (has_energy_trap<S>())
        if (energy_search_) verdict = wells_for(c).verdict;
      column(map.trap_verdict, k)[0] = static_cast<double>(verdict);
    }
    if (status == LaneStatus::ok && !finite) status = LaneStatus::non_finite;
    column(map.status, k)[0] = static_cast<double>(status);
    if (plan_.samples > 0 && status != LaneStatus::ok) {
      // A failed lane's trajectory ends where it failed: every sample not recorded while it was
      // healthy is NaN, including one due at the look that found it failed (b.n).
      for (auto s = b.samples_recorded; s < plan_.samples; ++s) {
        for (int i = 0; i < kMaxVars; ++i)
          if (map.traj_vars[i] >= 0) column(map.traj_vars[i], k)[s] = nan;
        if (map.traj_H >= 0) column(map.traj_H, k)[s] = nan;
      }
    }
  }

  // The label is provisional here (1: settled) except for the trap's ±1: the attractor table,
  // built once every block is done (attractor_table.hpp), numbers the attractors.
  void finish_basin(const Book& b, const LaneState<D>& x, LaneStatus status) {
    const auto& map = plan_.map;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const bool ok = status == LaneStatus::ok && decided(b);
    double label = 0.0;
    if (ok && b.trapped) {
      // With early stop the label is taken when the trap closes; integrated to t_end it is the
      // well the lane ends in. Both agree unless the margin were too small (tested).
      label = x.q[0] > 0.0 ? 1.0 : -1.0;
    } else if (map.basin_point >= 0) {
      double* point = column(map.basin_point, b.point);
      for (int k = 0; k <= N; ++k) point[k] = nan;
      if (ok) {
        label = 1.0;
        for (int k = 0; k < N; ++k) point[k] = b.attractor[static_cast<std::size_t>(k)];
        point[N] = b.period;
      }
    }
    column(map.basin, b.point)[0] = label;
    column(map.settle_time, b.point)[0] = ok ? b.settle_time : nan;
  }

  // False if a value it wrote is not finite where one exists (the frequency ratio of an
  // oscillator at rest, sync_amplitude = 0, does not).
  bool finish_sync(const Book& b, LaneStatus status) {
    const auto& map = plan_.map;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    SyncResult r{nan, nan, nan, nan};
    if (status == LaneStatus::ok && b.n >= sync_n1_)
      r = b.sync.result(static_cast<double>(sync_n1_ - sync_n0_) * plan_.spec.h);
    column(map.sync_r, b.point)[0] = r.r;
    column(map.sync_phase_drift, b.point)[0] = r.phase_drift;
    column(map.sync_freq_ratio, b.point)[0] = r.freq_ratio;
    column(map.sync_amplitude, b.point)[0] = r.amplitude;
    if (!(status == LaneStatus::ok && b.n >= sync_n1_)) return true;  // nothing measured
    return std::isfinite(r.r) && std::isfinite(r.phase_drift) && std::isfinite(r.amplitude) &&
           (std::isfinite(r.freq_ratio) || r.amplitude == 0.0);
  }

  const RunPlan& plan_;
  BlockResults& out_;
  Params uniform_params_{};
  Coef uniform_coef_{};
  LaneState<D> idle_{};
  std::int64_t steps_ = 0, next_ = 0, sync_n0_ = 0, sync_n1_ = 0;
  double t_start_ = 0.0, h_ = 0.0;
  int remainder_ = 0, active_ = 0, fin_count_ = 0;
  bool basin_early_stop_ = true;
  bool strobe_ = false;       // attractors looked for on the stroboscopic map (Book::cycle)
  std::unique_ptr<CycleTracker<N>[]> main_cycles_, fin_cycles_;  // per slot, when strobe_
  bool look_search_ = false;  // attractors looked for at every look (anchor_, near_)
  bool energy_search_ = false;  // the energy trap of K = T + V + k·z (energy_wells.hpp)
  BasinBox<D> grid_box_{};  // the map's positions, widened (basin_box)
  BasinBox<D> box_{};       // the wells' box when Uniform (else per lane: box_lo_, box_hi_)
  double angle_period_[N] = {}, angle_frequency_[N] = {};
  Tile main_{}, fin_{};
  Book main_book_[W], fin_book_[W];
  // Screening state of the main tile, structure of arrays.
  alignas(64) std::int64_t steps_done_[W];  // the main tile's step counts (Book::n is set
                                            // from it when a lane is looked at)
  alignas(64) LookInt countdown_[W];
  alignas(64) LookInt attention_[W];
  alignas(64) double trap_energy_[W];
  alignas(64) double a2_[W];
  alignas(64) double anchor_[N][W];      // where each lane's current run near a point began
  alignas(64) double near_[W];           // looks since then, all within the tolerance
  alignas(64) double dwell_needed_[W];   // looks that settle a lane (∞: not searching)
  alignas(64) double well_energy_[W];    // the lane's trap level (−∞: none)
  alignas(64) double box_lo_[Uniform ? 1 : D][W];  // the lane's wells' box (not Uniform)
  alignas(64) double box_hi_[Uniform ? 1 : D][W];
};

}  // namespace cs
