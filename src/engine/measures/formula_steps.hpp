// What measures as formulas do after every step of a tile (engine/measures/observables.hpp): the
// stop's flags and observe_window's every-step samples, vectorised over the tile. Apart from the
// tracker, so that the same code runs inside a whole kernel's step loop and inside a step
// kernel's (engine/step_kernel_entry.hpp, advance_watched), where the program's tracker hands it
// its FormulaSteps: the same operations, so the same bits.
#pragma once

#include <cmath>
#include <cstdint>

#include "engine/lane_clock.hpp"
#include "engine/measures/observable_view.hpp"
#include "engine/run_traits.hpp"
#include "numerics/lane_math.hpp"
#include "numerics/lane_state.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

// Per-slot state of the every-step work (slots 0 … W−1 the main tile's, W … 2W−1 the
// finisher's), room for K observables: the lanes' step counts at the advance's start, the stop's
// flags, the window's sums, extremes, counts and NaN marks; whether this advance reaches the
// window, and the window's steps.
template <int K, int W>
struct FormulaSteps {
  alignas(64) std::int64_t base[2 * W];
  alignas(64) LookInt hit[2 * W];
  alignas(64) double sum[K][2 * W];
  alignas(64) double min[K][2 * W];
  alignas(64) double max[K][2 * W];
  alignas(64) double count[2 * W];
  alignas(64) double nan[2 * W];
  bool window_now = false;
  std::int64_t window_first = 0, window_last = -1;
};

// λ of a lane as a formula reads it: exp(ln λ), ln λ as final_log_lambda (lane_state.hpp).
template <Scene S, class M>
double formula_lambda(const LaneState<S::dof>& x) {
  return FormulaTraits<M>::reads_lambda() ? std::exp(log_lambda<S>(x)) : 1.0;
}

template <Scene S, class M>
ObservableView<S::dof> formula_view(const LaneState<S::dof>& x, double t) {
  return {x.q, x.p, x.z, t, formula_lambda<S, M>(x)};
}

// Lane i of the tile as the step sees it (the fields the run carries).
template <Scene S, Carry carry, class Tile>
LaneState<S::dof> formula_lane(const Tile& t, int i) {
  LaneState<S::dof> x;
  for (int d = 0; d < S::dof; ++d) x.q[d] = t.q[d][i], x.p[d] = t.p[d][i];
  if constexpr (carry.z || S::z_feeds_back) x.z = t.z[i]; else x.z = 0.0;
  if constexpr (carry.mu) {
    x.mu = t.mu[i];
    x.lambda_numerator = t.lambda_numerator[i];
    x.lambda_denominator = t.lambda_denominator[i];
    x.lambda_folds = t.lambda_folds[i];
  } else {
    x.mu = 0.0;
  }
  return x;
}

// After step s of an advance of tile `which` (its lanes at step base + s + 1): the stop's flags,
// and the window's every-step samples where the advance reaches the window. Parameters from
// `uniform` when Uniform, else from the tile.
template <Scene S, Carry carry, bool Uniform, class M, int K, int W, class Tile>
inline void formula_after_step(const Tile& t, int which, int s, FormulaSteps<K, W>& a,
                               LaneClock clock, const ParamsOf<S, double>& uniform) {
  constexpr int D = S::dof;
  const int b = which * W;
  auto params = [&](int i) {
    if constexpr (Uniform) return uniform;
    else return t.params(i);
  };
  if constexpr (M::stop) {
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LaneState<D> x = formula_lane<S, carry>(t, i);
      const double time = clock.at(a.base[b + i] + s + 1);
      a.hit[b + i] |= static_cast<LookInt>(M::stops(formula_view<S, M>(x, time), params(i)));
    }
  }
  if constexpr (M::observables > 0) {
    if (!a.window_now) return;
    // Branch-free, so that it vectorises: a sample outside the window adds +0.0 to the sum
    // (which is never −0.0: it starts at +0.0), and leaves min, max, count as they are.
    const std::int64_t first = a.window_first, last = a.window_last;
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      const int slot = b + i;
      const std::int64_t n = a.base[slot] + s + 1;
      const bool in = (n >= first) & (n <= last);
      LaneState<D> x = formula_lane<S, carry>(t, i);
      double v[M::observables];
      M::observe(formula_view<S, M>(x, clock.at(n)), params(i), v);
      double nan_seen = a.nan[slot];
      for (int k = 0; k < M::observables; ++k) {
        const double mn = a.min[k][slot], mx = a.max[k][slot];
        a.sum[k][slot] = a.sum[k][slot] + lane_math::select(in, v[k], 0.0);
        a.min[k][slot] = lane_math::select(in & (v[k] < mn), v[k], mn);
        a.max[k][slot] = lane_math::select(in & (v[k] > mx), v[k], mx);
        nan_seen = lane_math::select(in & (v[k] != v[k]), 1.0, nan_seen);
      }
      a.nan[slot] = nan_seen;
      a.count[slot] = a.count[slot] + lane_math::select(in, 1.0, 0.0);
    }
  }
}

}  // namespace cs
