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
//
// Basins are the mappers' (mappers/basin_mapper.hpp): the runner hands them the lanes at load,
// after each chunk (their screen) and at every look, and writes what they settled.
//
// An adaptive method (dop853): a chunk is `chunk` attempts of every lane, each lane at its own
// time (LaneTile::ad); a lane is looked at when it reaches t_end, and b.n counts its attempts
// (capped at kAdaptiveMaxSteps: a lane that needs more fails as a breakdown, as dop853.f's nmax);
// its trajectory, sync and stroboscopic samples come from its steps' dense output
// (dense_samples.hpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "engine/dense_samples.hpp"
#include "engine/lane_health.hpp"
#include "engine/lane_start.hpp"
#include "engine/lane_tile.hpp"
#include "engine/lane_writer.hpp"
#include "engine/mappers/mapper_set.hpp"
#include "engine/measures/lyapunov_lanes.hpp"
#include "engine/measures/observables.hpp"
#include "engine/run_plan.hpp"
#include "engine/run_traits.hpp"
#include "physics/partials.hpp"
#include "physics/scene_bounds.hpp"

namespace cs {

// `Formulas`: the run's observe and stop (engine/measures/observables.hpp), generated into the
// run-time kernel; none in the built-in kernels. `Mappers`: the basin mappers compiled in
// (mappers/mapper_choice.hpp); a run-time kernel has only its plan's, the built-in ones all.
// `DenseOutput`: whether an adaptive method's steps can build their continuous extension for
// samples inside them (samples_inside_steps), false in a run-time kernel whose plan takes none:
// a quarter of dop853's kernel. The advances with the tangent (lyapunov) or the stop build it
// whatever this says; the others (observe formulas included) only with it.
template <Scene S, class Method, Carry carry, bool Uniform, class Formulas = NoMeasureFormulas,
          MapperChoice Mappers = kEveryMapper, bool DenseOutput = true>
class BlockRunner {
  static constexpr bool kFormulas = kHasFormulas<Formulas>;
  static constexpr int W = 64;
  static constexpr int D = S::dof;
  using Tile = LaneTile<S, Method, W>;
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;
  using Book = LaneBook<D>;
  static constexpr bool kAdaptive = adaptive_method<Method>();
  static constexpr std::int64_t kAdaptiveMaxSteps = 100000;

 public:
  BlockRunner(const RunPlan& plan, BlockResults& out)
      : plan_(plan),
        out_(out),
        writer_(plan, out),
        uniform_params_(S::params_from(plan.grid.base_parameters().data())),
        clock_{plan.spec.t_start, plan.spec.h},
        mappers_(plan, clock_, uniform_params_),
        formulas_(plan, out, clock_, uniform_params_) {
    LaneState<D> x{};
    x.t = clock_.t_start;
    uniform_coef_ = Method::template coefficients<S>(plan.spec.h, uniform_params_, x);
    steps_ = plan.spec.steps;
    if constexpr (kAdaptive) {
      steps_ = (kAdaptiveMaxSteps + plan.chunk - 1) / plan.chunk * plan.chunk;
      const typename Method::Control control{plan.spec.rtol, plan.spec.atol, plan.spec.t_end,
                                             plan.spec.t_end - plan.spec.t_start};
      main_.ad.control = fin_.ad.control = control;
      main_.ad.sampling = fin_.ad.sampling = dense_samples_.any() || lyapunov_.marks_in_steps();
      if (!DenseOutput && dense_samples_.any())
        throw std::logic_error("the kernel was compiled without the dense output this run samples");
    }
    remainder_ = static_cast<int>(steps_ % plan.chunk);
    const auto& m = plan.spec.measures;
    sync_n0_ = plan.sync_first_step;
    sync_n1_ = plan.sync_last_step;
    if (m.basin) basin_early_stop_ = m.basin->early_stop;
    idle_ = start_lane<S, Method>(plan_, out_.range.begin - plan_.point_offset, clock_.t_start).x;
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

  // Slots 0 … W − 1 are the main tile's, W … 2W − 1 the finisher's (as the mappers count them).
  int slot(const Tile& t, int i) const { return &t == &main_ ? i : W + i; }

  void clear(Tile& t, Book* book, int i) {
    t.set_lane(i, idle_);
    t.set_parameters(i, uniform_params_, uniform_coef_);
    book[i] = Book{};
    t.steps_done[i] = 0.0;
    if constexpr (kAdaptive) t.ad.clear(i, plan_.spec.t_end, 0.0);  // idle: attempts nothing
    lyapunov_.clear(&t == &main_, i);
    mappers_.clear(slot(t, i));
    if constexpr (kFormulas) formulas_.clear(slot(t, i));
    if (&t == &main_) {
      first_chunk_[i] = chunks_;
      countdown_[i] = std::numeric_limits<LookInt>::max();
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
  // Cold, as finish(): once per lane, so GCC compiles it for size and keeps it out of run(),
  // which a new K's compile pays for in every kernel (docs/performance.md, "cold code").
  [[gnu::cold]] bool load(int i, std::int64_t k) {
    auto [x, c] = start_lane<S, Method>(plan_, k - plan_.point_offset, clock_.t_start);
    Coef coef = Method::template coefficients<S>(plan_.spec.h, c, x);
    Book b;
    b.point = k;
    b.sync_n = sync_n0_;
    if (plan_.map.sync_r >= 0) set_sync_omega(b, c);
    if constexpr (kFormulas) formulas_.clear(i);
    if (!defined_at<S>(x, c)) {  // no dynamics to integrate: K or a partial is not finite
      finish(i, b, x, c, LaneStatus::undefined_at_start);
      return false;
    }
    if (Method::template breaks_down<S>(coef)) {
      observe(i, b, x, c);  // the initial state is sound; its first step is what breaks down
      finish(i, b, x, c, LaneStatus::breakdown);
      return false;
    }
    if constexpr (kFormulas) {
      if (formulas_.load(i, x, c)) {  // the stop's condition holds at the start
        finish_stopped(i, b, x, c);
        return false;
      }
    }
    observe(i, b, x, c);
    if (b.basin.settled && basin_early_stop_) {  // decided before the first step
      finish(i, b, x, c, LaneStatus::ok);
      return false;
    }
    main_.set_lane(i, x);
    main_.set_parameters(i, c, coef);
    lyapunov_.seed(i, x, c);
    if constexpr (kAdaptive) {
      main_.ad.clear(i, clock_.t_start, plan_.spec.h);
      main_.ad.next_sample[i] = std::min(dense_samples_.next(b), lyapunov_.next_mark(i));
    }
    main_book_[i] = b;
    first_chunk_[i] = chunks_;
    countdown_[i] = chunks_until_due(0);
    mappers_.arm(i, x, c, b.basin);
    ++active_;
    if (steps_ < plan_.chunk) move_to_finisher(i);  // a run shorter than one chunk
    return true;
  }

  // ---- stepping ------------------------------------------------------------------------------

  void advance_tile(Tile& t, int steps) {
    const int which = &t == &main_ ? 0 : 1;
    // The lanes' step counts, for the tangent and for the formulas' work after every step: a
    // pass over the tile a chunk, skipped where nothing reads them (on a step kernel a K's
    // observables at its end alone cost 6 % of a map in it).
    std::int64_t base[W];
    bool count_steps = carry.tangent;
    if constexpr (kFormulas) count_steps = count_steps || formulas_.after_every_step();
    if (count_steps)
      for (int i = 0; i < W; ++i) base[i] = which == 0 ? steps_done(i) : fin_book_[i].n;
    if constexpr (carry.tangent && kAdaptive) {
      auto on_dense = [&](int i, const auto& dense) { dense_step(t, i, dense); };
      if constexpr (Formulas::stop) {
        lyapunov_.template advance_adaptive_tile<Uniform>(
            t, which == 0, steps, uniform_params_, on_dense,
            [&](int i) { return formulas_.stops_now(t, i); });
      } else {
        lyapunov_.template advance_adaptive_tile<Uniform>(t, which == 0, steps, uniform_params_,
                                                          on_dense, nullptr);
      }
    } else if constexpr (carry.tangent) {
      bool hooks = false;
      if constexpr (kFormulas) hooks = formulas_.before_advance(t, which, base, steps);
      lyapunov_.template advance<Uniform>(t, which == 0, base, steps, uniform_params_,
                                          uniform_coef_, clock_.t_start, clock_.h, [&](int s) {
                                            if constexpr (kFormulas)
                                              if (hooks) formulas_.after_step(t, which, s);
                                          });
    } else if constexpr (kAdaptive) {  // its formulas read samples and the stop's condition
                                        // (no every-step window: spec_integrator.cpp)
      auto on_dense = [&](int i, const auto& dense) { dense_step(t, i, dense); };
      if constexpr (Formulas::stop) {
        auto stops = [&](int i) { return formulas_.stops_now(t, i); };
        advance_adaptive<S, Method, carry, Uniform>(t, steps, uniform_params_, [](int) {},
                                                    on_dense, stops);
      } else if constexpr (DenseOutput) {
        advance_adaptive<S, Method, carry, Uniform>(t, steps, uniform_params_, [](int) {},
                                                    on_dense);
      } else {  // no sample inside a step (checked at construction): the steps alone
        advance_adaptive<S, Method, carry, Uniform>(t, steps, uniform_params_, [](int) {});
      }
    } else if constexpr (kFormulas) {
      if (formulas_.before_advance(t, which, base, steps)) {
        if constexpr (FormulaTraits<Formulas>::in_step_kernel)  // its step loop does the work
          formulas_.advance_in_kernel(t, which, steps, uniform_params_, uniform_coef_);
        else
          advance<S, Method, carry, Uniform>(t, steps, uniform_params_, uniform_coef_,
                                             clock_.t_start, clock_.h,
                                             [&](int s) { formulas_.after_step(t, which, s); });
        return;
      }
      advance<S, Method, carry, Uniform>(t, steps, uniform_params_, uniform_coef_, clock_.t_start,
                                         clock_.h, [](int) {});
    } else {
      advance<S, Method, carry, Uniform>(t, steps, uniform_params_, uniform_coef_, clock_.t_start,
                                         clock_.h, [](int) {});
    }
  }

  // Lane i of tile t took a step that reached its next sample time or its stop (defined in
  // block_runner_stop.hpp).
  template <class Dense>
  void dense_step(Tile& t, int i, const Dense& dense);
  // Trajectory sample k of the lane in `lane_slot` (an adaptive lane's: n = k·every nominal
  // steps, the time the observables see).
  auto sample_at(int lane_slot) {
    return [this, lane_slot](Book& b, std::int64_t k, const LaneState<D>& x, const Params& c) {
      writer_.record_sample(b, k, x, c);
      if constexpr (kFormulas)
        formulas_.record_sample(lane_slot, b.point, k, k * plan_.spec.measures.trajectory->every,
                                x, c);
    };
  }
  auto sync_at() {
    return [this](Book& b, std::int64_t n, const LaneState<D>& x, const Params&) {
      sample_sync(b, n, x.q, x.p);
    };
  }
  // observe_window's sample at nominal step n of the lane in `lane_slot` (no trajectory).
  auto window_at(int lane_slot) {
    return [this, lane_slot](Book&, std::int64_t n, const LaneState<D>& x, const Params& c) {
      formulas_.window_sample(lane_slot, n, x, c);
    };
  }
  // The stroboscopic map's sample k of the lane in `lane_slot`, to the mappers that sample it.
  auto strobe_at(int lane_slot) {
    return [this, lane_slot](Book& b, std::int64_t k, const LaneState<D>& x, const Params& c) {
      mappers_.look_stroboscopic(lane_slot, k, x, c, b.basin);
    };
  }

  // The main tile's lane i: its steps since it was loaded, all whole chunks.
  std::int64_t steps_done(int i) const { return (chunks_ - first_chunk_[i]) * plan_.chunk; }

  // Which lanes need a closer look after a chunk: failed, or due for a sample or the end; then
  // the mappers' own screens. Branch-free over the tile so that it vectorises like the step.
  // The mappers' lane flags (the energy trap's E) are computed only while a lane can raise one:
  // once every lane of a run to t_end has settled, the pass is the bookkeeping alone.
  void screen() {
    ++chunks_;
    if (mappers_.flagging()) {
      mappers_.prepare_flags(main_);
      screen_for_scene<true>();
    } else {
      screen_for_scene<false>();
    }
    mappers_.screen(main_, attention_);
    if constexpr (kFormulas) formulas_.screen(attention_);
  }

  // The pass for the scene's traits: whether a lane's breakdown flag can be set (K_z not
  // constant) and whether its step count is read for its time. A proxy scene's are its step
  // kernel's (engine/proxy_scene.hpp), known at run time: each pairing is compiled and the run
  // picks its own, since checking what a scene never sets cost a K's map 9 %.
  template <bool kFlags>
  void screen_for_scene() {
    using Traits = SceneTraits<S, carry>;
    if constexpr (Traits::at_run_time) {
      const bool kz_constant = Traits::kz_constant(), reads_time = Traits::time_dependent();
      if (kz_constant && !reads_time) screen_pass<kFlags, false, false>();
      else if (kz_constant) screen_pass<kFlags, false, true>();
      else if (!reads_time) screen_pass<kFlags, true, false>();
      else screen_pass<kFlags, true, true>();
    } else {
      screen_pass<kFlags, !S::kz_constant || kAdaptive, time_dependent<S>()>();
    }
  }

  template <bool kFlags, bool kMayBreak, bool kReadsTime>
  void screen_pass() {
    Tile& t = main_;
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LookInt healthy = 1;
      if constexpr (kMayBreak) healthy = t.broken[i] <= 0.0;  // else never set
      for (int d = 0; d < D; ++d)
        healthy &= (std::fabs(t.q[d][i]) <= kDivergenceBound) & (std::fabs(t.p[d][i]) <= kDivergenceBound);
      countdown_[i] -= 1;
      if constexpr (kReadsTime) t.steps_done[i] += plan_.chunk;  // read for t alone
      LookInt due = countdown_[i] <= 0;
      if constexpr (kAdaptive) due |= t.ad.t[i] >= plan_.spec.t_end;
      LookInt a = (!healthy) | due;
      if constexpr (kFlags) a |= mappers_.flag(t, i);
      attention_[i] = a;
    }
  }

  // Chunks until a lane at step n is due for a sample, a mapper's look or the end of its run.
  // Clamped to LookInt: a countdown that runs out early only brings one more look, which sets
  // the next countdown.
  LookInt chunks_until_due(std::int64_t n) const {
    std::int64_t due = (steps_ / plan_.chunk) * plan_.chunk;
    if (plan_.samples > 0 && !kAdaptive) {  // an adaptive lane samples as it steps
      auto every = plan_.spec.measures.trajectory->every;
      due = std::min(due, (n / every + 1) * every);
    }
    if (plan_.map.sync_r >= 0 && n < sync_n1_)
      due = std::min(due, n < sync_n0_ ? sync_n0_ : n + plan_.chunk);
    due = std::min(due, mappers_.next_look(n));
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
      b.n = steps_done(i);
      if constexpr (Formulas::stop) {
        if (formulas_.hit(i)) {  // the stop's condition held after a step of this chunk
          stop_lane(i, main_, i, b, plan_.chunk);
          clear(main_, main_book_, i);
          --active_;
          continue;
        }
      }
      countdown_[i] = chunks_until_due(b.n);
      LaneState<D> x = main_.lane(i);
      x.t = clock_.at(b.n);
      bool at_end = b.n == steps_;
      if constexpr (kAdaptive) {
        x.t = main_.ad.t[i];
        if (at_end && x.t < plan_.spec.t_end) x.broken = 1.0;  // out of attempts
        at_end = x.t >= plan_.spec.t_end || at_end;
      }
      const Params c = main_.params(i);
      LaneStatus status = LaneStatus::ok;
      bool failed = lane_failed<S>(x, status);
      if (!failed) observe(i, b, x, c);
      if constexpr (kAdaptive)
        if (!failed && at_end)
          dense_samples_.at_end(b, x, c, sample_at(i), sync_at(), strobe_at(i), window_at(i));
      if (b.basin.settled) mappers_.disarm(i);  // nothing more to look for
      bool done = failed || at_end || (b.basin.settled && basin_early_stop_);
      if (done) {
        finish(i, b, x, c, status);
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
    if constexpr (kAdaptive) fin_.ad.copy(j, main_.ad, i);
    fin_book_[j] = main_book_[i];
    mappers_.move(i, W + j);
    lyapunov_.move(i, j);
    if constexpr (kFormulas) formulas_.move(i, W + j);
    clear(main_, main_book_, i);
    --active_;
  }

  void run_finisher() {
    advance_tile(fin_, remainder_);
    for (int j = 0; j < fin_count_; ++j) {
      Book& b = fin_book_[j];
      if constexpr (Formulas::stop) {
        if (formulas_.hit(W + j)) {
          stop_lane(W + j, fin_, j, b, remainder_);
          clear(fin_, fin_book_, j);
          continue;
        }
      }
      b.n += remainder_;
      LaneState<D> x = fin_.lane(j);
      x.t = clock_.at(b.n);
      LaneStatus status = LaneStatus::ok;
      lane_failed<S>(x, status);
      const Params c = fin_.params(j);
      if (status == LaneStatus::ok) observe(W + j, b, x, c);
      finish(W + j, b, x, c, status);
      clear(fin_, fin_book_, j);
    }
    fin_count_ = 0;
  }

  // ---- measures ------------------------------------------------------------------------------

  // Looks at the healthy lane in `lane_slot` at step b.n (a multiple of the chunk, or t_end).
  void observe(int lane_slot, Book& b, const LaneState<D>& x, const Params& c) {
    if (plan_.map.basin >= 0 && !b.basin.settled) mappers_.look(lane_slot, b.n, x, c, b.basin);
    // An adaptive lane's stroboscopic map: sample 0 here, the others from its steps.
    if constexpr (kAdaptive)
      if (b.n == 0) dense_samples_.at_start(b, x, c, strobe_at(lane_slot));
    // An adaptive lane's samples after the first come from its steps' dense output.
    if (plan_.samples > 0 && (!kAdaptive || b.n == 0)) {
      auto every = plan_.spec.measures.trajectory->every;
      if (b.n % every == 0) {
        writer_.record_sample(b, b.n / every, x, c);
        if constexpr (kFormulas) formulas_.record_sample(lane_slot, b.point, b.n / every, b.n, x, c);
        b.samples_recorded = b.n / every + 1;
      }
    }
    // An adaptive lane's sync samples after the first come from its steps' dense output.
    if (plan_.map.sync_r >= 0 && (!kAdaptive || b.n == 0) && b.n >= sync_n0_ &&
        b.n <= sync_n1_ && b.n % plan_.chunk == 0) {
      sample_sync(b, b.n, x.q, x.p);
      if constexpr (kAdaptive) b.sync_n = b.n + plan_.chunk;
    }
  }

  // The phases' ω: the spec's, else the scene's own (natural_frequencies, scene_concept.hpp).
  // A lane's parameters fix them: taken once, at its load, not at every sample (a step
  // kernel's scene answers through its table: a call per sample cost its sync maps ~5 %).
  void set_sync_omega(Book& b, const Params& c) {
    if constexpr (D >= 2) {
      const auto& sync = *plan_.spec.measures.sync;
      double omega[D];
      natural_frequencies<S>(c, omega);
      b.sync_omega[0] = omega[sync.dof[0]], b.sync_omega[1] = omega[sync.dof[1]];
      if (sync.omega) b.sync_omega[0] = (*sync.omega)[0], b.sync_omega[1] = (*sync.omega)[1];
    }
  }
  void sample_sync(Book& b, std::int64_t n, const double* q, const double* p) {
    if constexpr (D >= 2) {
      const auto& sync = *plan_.spec.measures.sync;
      const int i = sync.dof[0], j = sync.dof[1];
      b.sync.sample(n, sync_n0_, sync_n1_, q[i], p[i], q[j], p[j], b.sync_omega[0],
                    b.sync_omega[1]);
    }
  }

  // The lane in `lane_slot` (main or finisher, as the mappers count) hands its results over
  // (cold: once per lane, as load()).
  [[gnu::cold]] void finish(int lane_slot, const Book& b, const LaneState<D>& x, const Params& c,
              LaneStatus status, bool stopped = false, int exit = 0) {
    TrapVerdict verdict = TrapVerdict::not_applicable;
    if (plan_.map.trap_verdict >= 0) verdict = mappers_.trap_verdict(c);
    // The tangent's exponent marks its lane non_finite where it is: a copy of the book, made
    // only then (a copy per lane is a cost on a map whose lanes stop early).
    const Book* book = &b;
    Book marked;
    if constexpr (kAdaptive || carry.tangent) {
      marked = b;
      book = &marked;
    }
    if constexpr (kAdaptive)  // its lane-steps: the attempts it made, accepted or rejected
      if (lane_slot < W) marked.n = static_cast<std::int64_t>(main_.ad.accepted[lane_slot] +
                                                              main_.ad.rejected[lane_slot]);
    if constexpr (carry.tangent) lyapunov_.finish(lane_slot, marked, status, x.t);
    writer_.finish(*book, x, c, status, verdict);
    if constexpr (kFormulas) formulas_.finish(lane_slot, *book, x, c, status, stopped, exit);
    if constexpr (Mappers.recur) {  // the recurrences' columns (none without them)
      if (plan_.map.basin_cells < 0) return;
      double record[RecurrenceSearch::kRecordWidth];
      UndecidedReason why = UndecidedReason::not_tracked;
      mappers_.recurrence_record(lane_slot, status != LaneStatus::ok, b.basin, record, why);
      writer_.finish_recurrence(b.point, record, why);
    }
  }

  // ---- the stop (engine/measures/observables.hpp; defined in block_runner_stop.hpp) -----------

  // Lane i of tile t (in `lane_slot`), flagged in its last advance of `steps` steps from b.n:
  // stepped again to the stop (an adaptive lane: held there), and finished there.
  void stop_lane(int lane_slot, const Tile& t, int i, Book& b, int steps);
  // A healthy lane that stopped in state x: its sample there, if one is due, and its exit as
  // the basin's outcome — unless it settled first.
  void finish_stopped(int lane_slot, Book& b, const LaneState<D>& x, const Params& c);

  const RunPlan& plan_;
  BlockResults& out_;
  LaneWriter<S> writer_;
  Params uniform_params_{};
  Coef uniform_coef_{};
  LaneClock clock_;
  DenseSamples<S> dense_samples_{plan_, clock_};  // an adaptive method's samples
  LaneState<D> idle_{};
  std::int64_t steps_ = 0, next_ = 0, sync_n0_ = 0, sync_n1_ = 0;
  int remainder_ = 0, active_ = 0, fin_count_ = 0;
  bool basin_early_stop_ = true;
  MapperSet<S, Uniform, W, Mappers> mappers_;
  LyapunovLanes<S, Method, carry, W> lyapunov_{plan_, out_};
  FormulaTracker<S, Method, carry, Uniform, Formulas, W> formulas_;
  Tile main_{}, fin_{};
  Book main_book_[W], fin_book_[W];
  // Screening state of the main tile, structure of arrays. The main tile's step counts (Book::n is set from them when a lane is looked at): the chunks
  // advanced, and per lane the count when it was loaded; one add per chunk, not one per lane.
  std::int64_t chunks_ = 0;
  alignas(64) std::int64_t first_chunk_[W];
  alignas(64) LookInt countdown_[W];
  alignas(64) LookInt attention_[W];
};

}  // namespace cs

#include "engine/block_runner_stop.hpp"  // NOLINT(build/include): the stop's member definitions
