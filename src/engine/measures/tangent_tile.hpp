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

// Every lane's tangent brought back into [2^-256, 2^256) (fold_scale).
template <Scene S, int W>
inline void fold_tile(TangentTile<S, W>& g) {
  constexpr int D = S::dof, N = TangentTile<S, W>::N;
#pragma GCC ivdep
  for (int i = 0; i < W; ++i) {
    double m = 0.0;
    for (int k = 0; k < N; ++k) m = std::fmax(m, std::fabs(g.v[k][i]));
    const double scale = fold_scale(m, g.folds[i]);
    for (int k = 0; k < N; ++k) g.v[k][i] = g.v[k][i] * scale;
    for (int d = 0; d < D; ++d) g.dkq[d][i] = g.dkq[d][i] * scale;
  }
}

// advance() (lane_tile.hpp) with the tangent: the same lane loop over the same step, on duals;
// after_step(s) after step s (and its fold), as advance() calls it.
template <Scene S, class Method, Carry carry, bool Uniform, int W, class AfterStep>
inline void advance_with_tangent(LaneTile<S, Method, W>& t, TangentTile<S, W>& g, int steps,
                                 const ParamsOf<S, double>& uniform,
                                 const typename Method::template Coef<double>& uniform_coef,
                                 double t_start, double h, AfterStep&& after_step) {
  constexpr int D = S::dof;
  constexpr bool with_z = carry.z || S::z_feeds_back;
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
    if (fold_due(s, steps)) fold_tile(g);
    after_step(s);
  }
}

// An adaptive method's tangent (advance_adaptive's `tangent` hook, lane_tile.hpp): the
// variational equation δy' = J(y)·δy integrated in the same stages as the state. Each stage
// runs on duals (Method::stage with T = Dual<double>): value parts the plain stage's operations
// (every other dataset keeps its bits), derivative parts J(y_k)·δy_k with δy_k the stage's
// tangent, kept in `dr`; an accepted step moves the tangent by the 8th-order weights
// (Method::advance_tangent), a rejected one leaves it. This is exactly the tangent of the
// accepted Runge–Kutta map at the step h the lane took (an explicit Runge–Kutta method commutes
// with linearisation), h itself not differentiated.
//
// Error control on the state alone: the tangent is linear in its seed and rescaled by powers of
// two, so an error norm over it would make a lane's steps depend on its seed and on when it was
// rescaled, and would let the tangent's growth along an unstable direction (the very thing
// measured) shrink the steps of the state; with the state's steps alone, a lane takes the same
// steps with or without `lyapunov`, and its other datasets keep their bits. (The usual choice:
// DynamicalSystemsBase's tangent integrator, behind ChaosTools' exponents, measures its error on
// the state column alone by default.) The fold (fold_tile: powers of two, exact) runs every 32 attempts and
// after the last, as in the fixed-step advance; it commutes with every rounding of the linear
// tangent, so the exponent does not depend on when it runs, only on the lane's own steps.
//
// With `stop` or `observe_window` (want_dense), a lane whose step may hold its stop or a
// window's end keeps its tangent before the step, and an accepted step that does gets the
// continuous extension of the state with its tangent (Dop853Dense on duals: four more stages on
// duals), from which the runner reads the tangent there (LyapunovLanes::at_stop, in_step). A
// step that holds only other samples (trajectory, sync, the stroboscopic map) does not: its
// lane's next window end, mark_at, lies past it.
// wz, wmu: the components the step integrates.
template <Scene S, int W, bool wz, bool wmu>
struct AdaptiveTangent {
  static constexpr int D = S::dof;
  static constexpr bool with_z = tangent_has_z<S>();
  using P = contact_field::Point<D, double>;
  using PT = contact_field::Point<D, Tangent>;

  TangentTile<S, W>& g;
  bool want_dense = false;
  alignas(64) double dr[12][2 * D + 1][W];  // the stages' tangent rates: δq.., δp.., δz
  alignas(64) double v_before[2 * D + 1][W];  // the tangent before the step (want_dense)
  alignas(64) double mark_at[W];  // each lane's next window end (+∞: none), kept by the runner
  Dop853Dense<S, wz, wmu, Tangent> dense{};   // the last step's extension with its tangent

  // Lane i's state point y and rate r with tangent parts from v and dr[j] (rows of 2D + 1).
  [[gnu::always_inline]] static PT with_tangent(const P& y, const double (*v)[W], int i) {
    PT out;
    for (int d = 0; d < D; ++d) out.q[d] = {y.q[d], v[d][i]}, out.p[d] = {y.p[d], v[D + d][i]};
    out.z = {y.z, with_z ? v[2 * D][i] : 0.0};
    out.mu = {y.mu, 0.0};
    return out;
  }

  // Lane i may reach its stop in this step: its tangent before it.
  void save_before(int i) {
    if (!want_dense) return;
    for (int k = 0; k < 2 * D + 1; ++k) v_before[k][i] = g.v[k][i];
  }

  // Lane i's accepted step from (t0, y0) to y1 (values) with its stage rates r, h the step:
  // the extension with its tangent into `dense`.
  template <class C>
  void build_dense(int i, const P& y0, const P& y1, const P* r, const C& c, double t0,
                   double h) {
    if (!want_dense) return;
    PT rt[12];
    for (int j = 0; j < 12; ++j) rt[j] = with_tangent(r[j], dr[j], i);
    dense = Dop853Dense<S, wz, wmu, Tangent>::build(with_tangent(y0, v_before, i),
                                                    with_tangent(y1, g.v, i), rt, c, t0, h);
  }

  // Stage k of lane i from y0 (values; the tangent from g) with the rates r[0 … k − 1]: its
  // rate, its tangent rate kept in dr[k].
  template <int k, class Method, bool stage_z, bool stage_mu, class C>
  [[gnu::always_inline]] P stage(int i, const P& y0, const C& c, double t, double hs,
                                 const P* r) {
    static_assert(stage_z == wz && stage_mu == wmu);
    const PT y = with_tangent(y0, g.v, i);
    PT rt[k > 0 ? k : 1];
    for (int j = 0; j < k; ++j) rt[j] = with_tangent(r[j], dr[j], i);
    const PT rk = Method::template stage<k, S, wz, wmu>(y, c, t, hs, rt);
    P out;
    for (int d = 0; d < D; ++d) {
      out.q[d] = rk.q[d].v, out.p[d] = rk.p[d].v;
      dr[k][d][i] = rk.q[d].d, dr[k][D + d][i] = rk.p[d].d;
    }
    out.z = rk.z.v, out.mu = rk.mu.v;
    if constexpr (with_z) dr[k][2 * D][i] = rk.z.d;
    return out;
  }

  // Lane i's attempt of step hs is over: its tangent moved where it was accepted.
  template <class Method>
  [[gnu::always_inline]] void conclude(int i, double hs, bool accepted) {
    P v0, rates[12];
    for (int d = 0; d < D; ++d) v0.q[d] = g.v[d][i], v0.p[d] = g.v[D + d][i];
    v0.z = with_z ? g.v[2 * D][i] : 0.0;
    v0.mu = 0.0;
    for (int j = 0; j < 12; ++j) {
      for (int d = 0; d < D; ++d) rates[j].q[d] = dr[j][d][i], rates[j].p[d] = dr[j][D + d][i];
      rates[j].z = with_z ? dr[j][2 * D][i] : 0.0;
      rates[j].mu = 0.0;
    }
    P v1 = v0;
    Method::template advance_tangent<D, with_z>(v1, v0, hs, rates);
    for (int d = 0; d < D; ++d) {
      g.v[d][i] = lane_math::select(accepted, v1.q[d], v0.q[d]);
      g.v[D + d][i] = lane_math::select(accepted, v1.p[d], v0.p[d]);
    }
    if constexpr (with_z) g.v[2 * D][i] = lane_math::select(accepted, v1.z, v0.z);
  }

  // After attempt s of `steps`.
  void after_attempt(int s, int steps) {
    if (fold_due(s, steps)) fold_tile(g);
  }
};

}  // namespace cs
