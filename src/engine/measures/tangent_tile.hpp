// The tangent vectors of a tile's lanes (structure of arrays beside the LaneTile) and the tile's
// advance with them: the step on Dual<double> lanes (tangent_lyapunov.hpp explains the
// measure). Used by BlockRunner when the run carries the tangent (Carry::tangent).
#pragma once

#include "engine/lane_tile.hpp"
#include "engine/measures/tangent_lyapunov.hpp"

namespace cs {

template <Scene S, int W>
struct TangentTile {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D + (tangent_has_z<S>() ? 1 : 0);  // components in the norm
  alignas(64) double v[2 * D + 1][W];
  alignas(64) double dkq[D][W];
  alignas(64) double folds[W];

  LaneTangent<D> lane(int i) const {
    LaneTangent<D> w;
    for (int k = 0; k < 2 * D + 1; ++k) w.v[k] = v[k][i];
    for (int d = 0; d < D; ++d) w.dkq[d] = dkq[d][i];
    w.folds = folds[i];
    return w;
  }
  void set_lane(int i, const LaneTangent<D>& w) {
    for (int k = 0; k < 2 * D + 1; ++k) v[k][i] = w.v[k];
    for (int d = 0; d < D; ++d) dkq[d][i] = w.dkq[d];
    folds[i] = w.folds;
  }
};

// The largest component magnitude m of a tangent brought back into [2^-256, 2^256) (fold_scale),
// the tile's way: after every 32nd step of an advance and after its last.
inline bool fold_due(int s, int steps) { return (s & 31) == 31 || s + 1 == steps; }

// advance() (lane_tile.hpp) with the tangent: the same lane loop over the same step, on duals;
// after_step(s) after step s (and its fold), as advance() calls it.
template <Scene S, class Method, Carry carry, bool Uniform, int W, class AfterStep>
inline void advance_with_tangent(LaneTile<S, Method, W>& t, TangentTile<S, W>& g, int steps,
                                 const ParamsOf<S, double>& uniform,
                                 const typename Method::template Coef<double>& uniform_coef,
                                 double t_start, double h, AfterStep&& after_step) {
  constexpr int D = S::dof;
  constexpr bool with_z = carry.z || S::z_feeds_back;
  constexpr int N = TangentTile<S, W>::N;
  const ParamsOf<S, double> c0 = uniform;  // plain doubles: K on nested duals costs less
  const TangentCoef<Method> k0 = coef_for_tangent<Method>(uniform_coef);
  for (int s = 0; s < steps; ++s) {
#pragma GCC ivdep
    for (int i = 0; i < W; ++i) {
      LaneState<D, Tangent> x;
      for (int d = 0; d < D; ++d) {
        x.q[d] = {t.q[d][i], g.v[d][i]};
        x.p[d] = {t.p[d][i], g.v[D + d][i]};
        x.kq[d] = {t.kq[d][i], g.dkq[d][i]};
      }
      if constexpr (with_z)
        x.z = {t.z[i], tangent_has_z<S>() ? g.v[2 * D][i] : 0.0};
      else
        x.z = {0.0, 0.0};
      if constexpr (carry.mu)
        x.mu = {t.mu[i], 0.0};
      else
        x.mu = {0.0, 0.0};
      if constexpr (carry.mu && !S::kz_constant) {
        x.lambda_numerator = {t.lambda_numerator[i], 0.0};
        x.lambda_denominator = {t.lambda_denominator[i], 0.0};
      }
      if constexpr (!S::kz_constant)
        x.broken = {t.broken[i], 0.0};
      else
        x.broken = {0.0, 0.0};
      if constexpr (time_dependent<S>())
        x.t = {t_start + (t.steps_done[i] + s) * h, 0.0};
      else
        x.t = {0.0, 0.0};
      if constexpr (Uniform) {
        Method::template step<S, carry>(x, c0, k0);
      } else {
        Method::template step<S, carry>(x, t.params(i),
                                        coef_for_tangent<Method>(t.coef(i)));
      }
      for (int d = 0; d < D; ++d) {
        t.q[d][i] = x.q[d].v, t.p[d][i] = x.p[d].v, t.kq[d][i] = x.kq[d].v;
        g.v[d][i] = x.q[d].d, g.v[D + d][i] = x.p[d].d, g.dkq[d][i] = x.kq[d].d;
      }
      if constexpr (with_z) t.z[i] = x.z.v;
      if constexpr (tangent_has_z<S>()) g.v[2 * D][i] = x.z.d;
      if constexpr (carry.mu) t.mu[i] = x.mu.v;
      if constexpr (carry.mu && !S::kz_constant) {
        t.lambda_numerator[i] = x.lambda_numerator.v;
        t.lambda_denominator[i] = x.lambda_denominator.v;
      }
      if constexpr (!S::kz_constant) t.broken[i] = x.broken.v;
    }
    fold_lambda_products<S, carry>(t, s, steps);
    // Growth of 2^256 takes far more than 32 steps of any lane that has not diverged.
    if (fold_due(s, steps)) {
#pragma GCC ivdep
      for (int i = 0; i < W; ++i) {
        double m = 0.0;
        for (int k = 0; k < N; ++k) m = std::fmax(m, std::fabs(g.v[k][i]));
        const double scale = fold_scale(m, g.folds[i]);
        for (int k = 0; k < N; ++k) g.v[k][i] = g.v[k][i] * scale;
        for (int d = 0; d < D; ++d) g.dkq[d][i] = g.dkq[d][i] * scale;
      }
    }
    after_step(s);
  }
}

}  // namespace cs
