// A tile: W lanes of one scene in structure-of-arrays form, small enough to stay in L1 while it
// is advanced for a chunk of steps (time-blocking). The step loop is outside, the lane loop
// inside: the compiler vectorises the lane loop (AVX2/AVX-512) and runs several vectors at once,
// which hides the latency of the step's long dependency chain.
//
// `Uniform` selects how parameters reach the lanes: when no grid axis is a scene parameter they
// are scalars the compiler keeps in registers (and folds a·a etc. out of the loop); otherwise
// each lane reads its own.
#pragma once

#include <array>
#include <cmath>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <algorithm>

#include "numerics/contact_field.hpp"
#include "numerics/dop853_dense.hpp"
#include "numerics/lane_state.hpp"
#include "numerics/method_description.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

// An adaptive method's lanes (numerics/methods/dop853.hpp): each its own time, the step it
// tries next, whether its last attempt was rejected, and its counts of accepted and rejected
// attempts; the controller's settings, one for the run. next_sample: the time of the lane's next
// sample (+∞ when none is due), which an accepted step reaching it interpolates (dense output,
// numerics/dop853_dense.hpp); `sampling` is false for a run with no samples, which then never
// looks.
template <class Method, int W, bool = adaptive_method<Method>()>
struct AdaptiveLanes {};
template <class Method, int W>
struct AdaptiveLanes<Method, W, true> {
  alignas(64) double t[W];
  alignas(64) double h[W];
  alignas(64) double last_rejected[W];
  alignas(64) double accepted[W];
  alignas(64) double rejected[W];
  alignas(64) double next_sample[W];
  typename Method::Control control{};
  bool sampling = false;
  void clear(int i, double t_start, double h_first) {
    t[i] = t_start;
    h[i] = std::min(h_first, control.h_max);
    last_rejected[i] = accepted[i] = rejected[i] = 0.0;
    next_sample[i] = INFINITY;
  }
  void copy(int to, const AdaptiveLanes& from, int i) {
    t[to] = from.t[i], h[to] = from.h[i], last_rejected[to] = from.last_rejected[i];
    accepted[to] = from.accepted[i], rejected[to] = from.rejected[i];
    next_sample[to] = from.next_sample[i];
  }
};

// ParamFields, CoefFields: the tile's room for parameters and coefficients, the scene's and the
// method's own by default. A step kernel's tile (engine/step_kernel.hpp) has the room of the
// program's runner over a proxy scene, so that both sides agree on where every field is; a lane
// then uses the first fields and leaves the rest alone.
template <Scene S, class Method, int W,
          int ParamFields = static_cast<int>(sizeof(ParamsOf<S, double>) / sizeof(double)),
          int CoefFields =
              static_cast<int>(sizeof(typename Method::template Coef<double>) / sizeof(double))>
struct LaneTile {
  static constexpr int D = S::dof;
  static constexpr int width = W;
  static constexpr bool adaptive = adaptive_method<Method>();
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;

  alignas(64) double q[D][W];
  alignas(64) double p[D][W];
  alignas(64) double z[W];
  alignas(64) double mu[W];
  alignas(64) double lambda_numerator[W];  // see LaneState
  alignas(64) double lambda_denominator[W];
  alignas(64) double lambda_folds[W];
  alignas(64) double kq[D][W];
  alignas(64) double broken[W];
  alignas(64) double steps_done[W];  // each lane's step count n at the start of advance(),
                                     // kept by the runner for time-dependent scenes only
  // Per-lane parameters and method coefficients (used when not uniform), stored field by field:
  // the lane loop then reads each field with contiguous loads and vectorises. Stored as arrays
  // of structs (strided loads) they made per-lane runs (a grid axis over a scene parameter: g, gamma, a, omega) about
  // 4x slower per lane-step than uniform ones.
  static constexpr int kParamFields = ParamFields;
  static constexpr int kCoefFields = CoefFields;
  alignas(64) double param_field[kParamFields][W];
  alignas(64) double coef_field[kCoefFields][W];
  [[no_unique_address]] AdaptiveLanes<Method, W> ad;  // an adaptive method's alone

  Params params(int i) const { return gather<Params>(param_field, i); }
  Coef coef(int i) const { return gather<Coef>(coef_field, i); }
  void set_parameters(int i, const Params& c, const Coef& k) {
    scatter(param_field, i, c);
    scatter(coef_field, i, k);
  }

  LaneState<D> lane(int i) const {
    LaneState<D> x;
    for (int d = 0; d < D; ++d) x.q[d] = q[d][i], x.p[d] = p[d][i], x.kq[d] = kq[d][i];
    x.z = z[i];
    x.mu = mu[i];
    x.lambda_numerator = lambda_numerator[i];
    x.lambda_denominator = lambda_denominator[i];
    x.lambda_folds = lambda_folds[i];
    x.broken = broken[i];
    return x;
  }

  void set_lane(int i, const LaneState<D>& x) {
    for (int d = 0; d < D; ++d) q[d][i] = x.q[d], p[d][i] = x.p[d], kq[d][i] = x.kq[d];
    z[i] = x.z;
    mu[i] = x.mu;
    lambda_numerator[i] = x.lambda_numerator;
    lambda_denominator[i] = x.lambda_denominator;
    lambda_folds[i] = x.lambda_folds;
    broken[i] = x.broken;
  }

 private:
  // Params and Coef are aggregates of doubles only (checked), so a lane's fields rebuild the
  // struct bit for bit; a tile with more room than the struct uses its first fields. A struct
  // with room for any scene's (a proxy scene's, engine/proxy_scene.hpp) says how many of its
  // fields are in use (used_fields): only those are moved, since each field is a cache line of
  // its own in the tile, and a lane's load and end are on the runner's path.
  // The struct is filled in place, field by field: built in an array and bit_cast, it was read
  // back with one wide load of many narrow stores, which the CPU cannot forward (a stall of ~30
  // cycles on Zen 4 per lane looked at, most of a step kernel's sampling overhead).
  template <class Struct, int N>
  static Struct gather(const double (&field)[N][W], int i) {
    constexpr int n = fields_of<Struct, N>();
    Struct s{};
    int used = n;
    if constexpr (requires { Struct::used_fields(); }) used = Struct::used_fields();
    auto* bytes = reinterpret_cast<unsigned char*>(&s);
    for (int j = 0; j < used; ++j) std::memcpy(bytes + j * sizeof(double), &field[j][i], sizeof(double));
    return s;
  }
  template <class Struct, int N>
  static void scatter(double (&field)[N][W], int i, const Struct& s) {
    constexpr int n = fields_of<Struct, N>();
    int used = n;
    if constexpr (requires { Struct::used_fields(); }) used = Struct::used_fields();
    const auto values = std::bit_cast<std::array<double, n>>(s);
    for (int j = 0; j < used; ++j) field[j][i] = values[j];
  }
  template <class Struct, int N>
  static constexpr int fields_of() {
    constexpr int n = static_cast<int>(sizeof(Struct) / sizeof(double));
    static_assert(std::is_trivially_copyable_v<Struct> && sizeof(Struct) == n * sizeof(double) &&
                  n <= N);
    return n;
  }
};

// The fold's lane loop, kept out of the step loop's function: inlined there, GCC hoisted its
// five constants (2^±512, ±1 as bits) out of the step loop, and with AVX2's 16 registers the
// step of a state-dependent K_z (scene B, q p z ln λ) then spilt a vector to the stack and
// rebuilt a zero every pass (3 of its 59 instructions per vector). Called once per 64 steps.
template <int W>
[[gnu::noinline]] void fold_lambda_tile(double* __restrict folds, double* __restrict numerator,
                                   double* __restrict denominator) {
#pragma GCC ivdep
  for (int i = 0; i < W; ++i) {
    folds[i] = folds[i] + fold_power_of_two(numerator[i]);
    folds[i] = folds[i] - fold_power_of_two(denominator[i]);
  }
}

// The λ factors multiplied up by the hybrid leap-frog stay far from overflow if folded at
// least every 64 steps; when does not matter for the bits (log_lambda, lane_state.hpp). Called
// after step s of `steps`.
template <Scene S, Carry carry, class Method, int W, int PF, int CF>
[[gnu::always_inline]] inline void fold_lambda_products(LaneTile<S, Method, W, PF, CF>& t, int s,
                                                        int steps) {
  if constexpr (carry.mu && !S::kz_constant) {
    if ((s & 63) == 63 || s + 1 == steps)
      fold_lambda_tile<W>(t.lambda_folds, t.lambda_numerator, t.lambda_denominator);
  }
}

// An adaptive method: every lane makes `steps` attempts (numerics/methods/dop853.hpp), each
// from its own time with its own step; a lane at t_end attempts nothing. The lane's time, not a
// step count, is its clock. An attempt runs stage by stage over the whole tile, its rates kept
// in `rates` (12 × (2D + 2) × W doubles, in L1): each stage's lane loop is short and its lanes
// independent, so the out-of-order core overlaps them, where one attempt's 12 stages in a row
// are one dependency chain of ~400 instructions per vector, longer than the core's window. The
// same operations in the same order: the same bits as Method::attempt, lane by lane (checked on
// the double well's 512² map). The kernel's share of that map: 11 ns per lane-attempt, 1 core.
//
// Dense output (t.ad.sampling): a lane whose step may reach its next sample time keeps its state
// before the step; when the step is accepted and does reach it, on_dense(i, d) gets the step's
// continuous extension d (numerics/dop853_dense.hpp), built from that lane's stages alone, and
// sets the lane's next sample time. The steps themselves are those of a run without samples.
// With `watch` (the stop: engine/measures/observables.hpp) every lane keeps its state before
// each step, and a lane whose accepted step ends where watch(i) holds gets on_dense(i, d) too.
// With `tangent` (engine/measures/tangent_tile.hpp's AdaptiveTangent: the lyapunov measure)
// each stage runs with its tangent, and an accepted step moves the tangent too (and builds its
// continuous extension with the tangent's, for a stop inside it).
template <Scene S, class Method, Carry carry, bool Uniform, int W, class AfterStep,
          class OnDense = std::nullptr_t, class Watch = std::nullptr_t,
          class TangentHook = std::nullptr_t>
[[gnu::flatten]] inline void advance_adaptive(LaneTile<S, Method, W>& t, int steps,
                                              const ParamsOf<S, double>& uniform,
                                              AfterStep&& after_step,
                                              OnDense&& on_dense = nullptr,
                                              Watch&& watch = nullptr,
                                              TangentHook&& tangent = nullptr) {
  constexpr bool kWatch = !std::is_null_pointer_v<std::remove_cvref_t<Watch>>;
  constexpr bool kTangent = !std::is_null_pointer_v<std::remove_cvref_t<TangentHook>>;
  constexpr int D = S::dof;
  constexpr bool with_z = carry.z || S::z_feeds_back;
  constexpr bool with_mu = carry.mu && !S::kz_constant;
  constexpr int kStages = 12;
  using P = contact_field::Point<D, double>;
  const ParamsOf<S, double> c0 = uniform;
  const typename Method::Control control = t.ad.control;
  alignas(64) double rates[kStages][2 * D + 2][W];
  auto state = [&](int i) __attribute__((always_inline)) {
    P y;
    for (int d = 0; d < D; ++d) y.q[d] = t.q[d][i], y.p[d] = t.p[d][i];
    y.z = (carry.z || S::z_feeds_back) ? t.z[i] : 0.0;
    y.mu = carry.mu ? t.mu[i] : 0.0;
    return y;
  };
  // Rates 0 … k − 1 of lane i (the components a later stage reads: q, p, z where integrated,
  // ln λ's rate where carried).
  auto load_rates = [&](P* r, auto k, int i) __attribute__((always_inline)) {
    contact_field::unrolled<decltype(k)::value>([&](auto j) __attribute__((always_inline)) {
      for (int d = 0; d < D; ++d) r[j].q[d] = rates[j][d][i], r[j].p[d] = rates[j][D + d][i];
      r[j].z = with_z ? rates[j][2 * D][i] : 0.0;
      r[j].mu = carry.mu ? rates[j][2 * D + 1][i] : 0.0;
    });
  };
  for (int s = 0; s < steps; ++s) {
    contact_field::unrolled<kStages>([&](auto k) __attribute__((always_inline)) {
#pragma GCC ivdep
      for (int i = 0; i < W; ++i) {
        const double hs = Method::step_to_try(t.ad.t[i], t.ad.h[i], control);
        P r[kStages];
        load_rates(r, k, i);
        P rk;
        if constexpr (kTangent) {
          constexpr int kk = decltype(k)::value;
          if constexpr (Uniform) {
            rk = tangent.template stage<kk, Method, with_z, with_mu>(i, state(i), c0, t.ad.t[i],
                                                                     hs, r);
          } else {
            rk = tangent.template stage<kk, Method, with_z, with_mu>(i, state(i), t.params(i),
                                                                     t.ad.t[i], hs, r);
          }
        } else if constexpr (Uniform) {
          rk = Method::template stage<decltype(k)::value, S, with_z, with_mu>(state(i), c0,
                                                                              t.ad.t[i], hs, r);
        } else {
          rk = Method::template stage<decltype(k)::value, S, with_z, with_mu>(
              state(i), t.params(i), t.ad.t[i], hs, r);
        }
        for (int d = 0; d < D; ++d) rates[k][d][i] = rk.q[d], rates[k][D + d][i] = rk.p[d];
        if constexpr (with_z) rates[k][2 * D][i] = rk.z;
        if constexpr (carry.mu) rates[k][2 * D + 1][i] = rk.mu;
      }
    });
    // Lanes whose step, if accepted, reaches their next sample: their state before it.
    bool dense_due = false;
    alignas(64) double t_before[W];
    alignas(64) double h_before[W];  // the step each lane attempts
    bool may_reach[W];
    P y_before[W];
    if constexpr (!std::is_null_pointer_v<std::remove_cvref_t<OnDense>>) {
      if (t.ad.sampling || kWatch) {
        for (int i = 0; i < W; ++i) {
          h_before[i] = Method::step_to_try(t.ad.t[i], t.ad.h[i], control);
          t_before[i] = t.ad.t[i];
          may_reach[i] = kWatch || t.ad.t[i] + h_before[i] >= t.ad.next_sample[i];
          if (may_reach[i]) dense_due = true, y_before[i] = state(i);
          if constexpr (kTangent)
            if (may_reach[i]) tangent.save_before(i);
        }
      }
    }
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LaneState<D> x;
      for (int d = 0; d < D; ++d) x.q[d] = t.q[d][i], x.p[d] = t.p[d][i], x.kq[d] = 0.0;
      if constexpr (carry.z || S::z_feeds_back) x.z = t.z[i]; else x.z = 0.0;
      if constexpr (carry.mu) x.mu = t.mu[i]; else x.mu = 0.0;
      x.broken = t.broken[i];
      x.t = t.ad.t[i];
      P r[kStages];
      load_rates(r, std::integral_constant<int, kStages>{}, i);
      double lane_t = t.ad.t[i], lane_h = t.ad.h[i], last_rejected = t.ad.last_rejected[i];
      double accepted = t.ad.accepted[i], rejected = t.ad.rejected[i];
      Method::template conclude<S, carry>(x, lane_t, lane_h, last_rejected, accepted, rejected,
                                          control, r);
      if constexpr (kTangent)
        tangent.template conclude<Method>(i, Method::step_to_try(t.ad.t[i], t.ad.h[i], control),
                                          accepted > t.ad.accepted[i]);
      for (int d = 0; d < D; ++d) t.q[d][i] = x.q[d], t.p[d][i] = x.p[d];
      if constexpr (carry.z || S::z_feeds_back) t.z[i] = x.z;
      if constexpr (carry.mu) t.mu[i] = x.mu;
      t.broken[i] = x.broken;
      t.ad.t[i] = lane_t, t.ad.h[i] = lane_h, t.ad.last_rejected[i] = last_rejected;
      t.ad.accepted[i] = accepted, t.ad.rejected[i] = rejected;
    }
    if constexpr (!std::is_null_pointer_v<std::remove_cvref_t<OnDense>>) {
      if (dense_due) {
        for (int i = 0; i < W; ++i) {
          // Accepted (its time moved) and at its sample: the last step lands on t_end, which
          // may round below t_before + h; the runner takes a sample at t_end from the state.
          if (!(may_reach[i] && t.ad.t[i] > t_before[i])) continue;
          bool watched = false;  // the stop's condition holds at the step's end (pure)
          if constexpr (kWatch) watched = watch(i);
          if (!(t.ad.t[i] >= t.ad.next_sample[i] || watched)) continue;
          P r[kStages];
          load_rates(r, std::integral_constant<int, kStages>{}, i);
          const ParamsOf<S, double> c = Uniform ? c0 : t.params(i);
          const auto dense = Dop853Dense<S, with_z, with_mu>::build(
              y_before[i], state(i), r, c, t_before[i], h_before[i]);
          if constexpr (kTangent)  // read at the stop and at the window's ends alone
            if (watched || t.ad.t[i] >= tangent.mark_at[i])
              tangent.build_dense(i, y_before[i], state(i), r, c, t_before[i], h_before[i]);
          on_dense(i, dense);
        }
      }
    }
    if constexpr (kTangent) tangent.after_attempt(s, steps);
    after_step(s);
  }
}

// Advance every lane of the tile by `steps` steps, calling after_step(s) after step s.
// Parameters come from `uniform` (one set for all lanes) when Uniform, else from the tile.
// A time-dependent scene's lane is at time t_start + n·h, n from its own step count: the same
// bits wherever the lane runs, and no drift from adding h up.
template <Scene S, class Method, Carry carry, bool Uniform, int W, int PF, int CF, class AfterStep>
inline void advance(LaneTile<S, Method, W, PF, CF>& t, int steps,
                    const ParamsOf<S, double>& uniform,
                    const typename Method::template Coef<double>& uniform_coef, double t_start,
                    double h, AfterStep&& after_step) {
  if constexpr (adaptive_method<Method>()) {
    return advance_adaptive<S, Method, carry, Uniform>(t, steps, uniform, after_step);
  }
  constexpr int D = S::dof;
  const ParamsOf<S, double> c0 = uniform;
  const auto k0 = uniform_coef;
  for (int s = 0; s < steps; ++s) {
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LaneState<D> x;
      for (int d = 0; d < D; ++d) x.q[d] = t.q[d][i], x.p[d] = t.p[d][i], x.kq[d] = t.kq[d][i];
      if constexpr (carry.z || S::z_feeds_back) x.z = t.z[i]; else x.z = 0.0;
      if constexpr (carry.mu) x.mu = t.mu[i]; else x.mu = 0.0;
      if constexpr (carry.mu && !S::kz_constant) {
        x.lambda_numerator = t.lambda_numerator[i];
        x.lambda_denominator = t.lambda_denominator[i];
      }
      if constexpr (!S::kz_constant) x.broken = t.broken[i]; else x.broken = 0.0;
      if constexpr (time_dependent<S>()) x.t = t_start + (t.steps_done[i] + s) * h;
      else x.t = 0.0;
      if constexpr (Uniform) {
        Method::template step<S, carry>(x, c0, k0);
      } else {
        Method::template step<S, carry>(x, t.params(i), t.coef(i));
      }
      for (int d = 0; d < D; ++d) t.q[d][i] = x.q[d], t.p[d][i] = x.p[d], t.kq[d][i] = x.kq[d];
      if constexpr (carry.z || S::z_feeds_back) t.z[i] = x.z;
      if constexpr (carry.mu) t.mu[i] = x.mu;
      if constexpr (carry.mu && !S::kz_constant) {
        t.lambda_numerator[i] = x.lambda_numerator;
        t.lambda_denominator[i] = x.lambda_denominator;
      }
      if constexpr (!S::kz_constant) t.broken[i] = x.broken;
    }
    fold_lambda_products<S, carry>(t, s, steps);
    after_step(s);
  }
}

}  // namespace cs
