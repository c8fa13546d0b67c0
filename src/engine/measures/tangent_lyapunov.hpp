// The finite-time largest Lyapunov exponent of a lane, from the tangent map of the integrator's
// own step (INTERFACE.md, "Observables, events and Lyapunov exponents"; docs/lyapunov.md).
//
// The step, a template over its number type, runs on T = Dual<double> whose derivative parts
// hold the tangent vector v: one step maps (x, v) to (Φ(x), DΦ(x)·v), DΦ the exact Jacobian of
// the numerical map Φ (no finite differences); K's partials inside it evaluate on nested duals
// (physics/dual_math_nested.hpp). The value parts are the plain step's own operations, so every
// other dataset keeps its bits.
//
// The tangent is (δq, δp), and δz where z feeds back into the (q, p) dynamics (K_z depends on
// the state, or z enters K_q, K_p): then the map closes only on (q, p, z). Where it does not,
// (q, p) evolve on their own and δz is left out (its growth, driven by K_z, is not the orbit's
// chaos). ln λ never feeds back and is never part of the tangent. The force cache (LaneState::kq)
// carries its tangent too, since the next step starts from it.
//
// Renormalisation: the tangent is scaled by 2^∓256 whenever its largest component leaves
// [2^-256, 2^256) (checked every 32 steps and at the end of each advance), and the powers are
// counted. The linearised step is linear in v, and scaling by a power of two commutes exactly
// with every rounding, so the tangent's bits do not depend on when it was scaled: a lane has the
// same value on any ranks and threads, in the main tile or the finisher. lyapunov = (256·ln 2·folds
// + ln‖v_n‖ − ln‖v_0‖) / (n·h).
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "engine/lane_tile.hpp"
#include "numerics/lane_state.hpp"

namespace cs {

using Tangent = Dual<double>;

// Does the tangent include δz? Only where z feeds back into the dynamics.
template <Scene S>
constexpr bool tangent_has_z() {
  return S::z_feeds_back;
}

// Params and Coef (aggregates of doubles) as duals whose derivative parts are 0: the step's T.
template <template <class> class Struct>
Struct<Tangent> as_tangent(const Struct<double>& s) {
  constexpr int n = sizeof(Struct<double>) / sizeof(double);
  static_assert(sizeof(Struct<Tangent>) == n * sizeof(Tangent));
  const auto values = std::bit_cast<std::array<double, n>>(s);
  std::array<Tangent, n> duals;
  for (int j = 0; j < n; ++j) duals[j] = Tangent{values[j], 0.0};
  return std::bit_cast<Struct<Tangent>>(duals);
}
template <Scene S>
ParamsOf<S, Tangent> params_as_tangent(const ParamsOf<S, double>& c) {
  return as_tangent<S::template Params>(c);
}
template <class Method>
typename Method::template Coef<Tangent> coef_as_tangent(
    const typename Method::template Coef<double>& k) {
  return as_tangent<Method::template Coef>(k);
}

// The coefficients as the tangent step takes them: plain doubles where the method's step
// accepts them (Method::plain_coefficients: no products with zero derivative parts), else duals.
template <class Method>
constexpr bool plain_coefficients() {
  if constexpr (requires { Method::plain_coefficients; }) return Method::plain_coefficients;
  else return false;
}
template <class Method>
auto coef_for_tangent(const typename Method::template Coef<double>& k) {
  if constexpr (plain_coefficients<Method>()) return k;
  else return coef_as_tangent<Method>(k);
}
template <class Method>
using TangentCoef = decltype(coef_for_tangent<Method>(typename Method::template Coef<double>{}));

// The tangent of one lane: components in the order q.., p.., z; kq's tangent for the force cache.
template <int D>
struct LaneTangent {
  double v[2 * D + 1] = {};
  double dkq[D] = {};
  double folds = 0.0;
};

inline constexpr double kFoldUp = 0x1p256, kFoldDown = 0x1p-256;
inline constexpr double kFoldLog = 256 * 0x1.62e42fefa39efp-1;  // 256·ln 2 (an exact product)

// The factor that brings a tangent whose largest component magnitude is m back into
// [2^-256, 2^256) (2^∓256, or 1), and the power taken out into `folds`. Branch-free, for the
// tile's lane loop; an exactly zero tangent stays as it is.
[[gnu::always_inline]] inline double fold_scale(double m, double& folds) {
  const bool high = m >= kFoldUp, low = m < kFoldDown && m > 0.0;
  folds = folds + lane_math::select(high, 1.0, lane_math::select(low, -1.0, 0.0));
  return lane_math::select(high, kFoldDown, lane_math::select(low, kFoldUp, 1.0));
}

// The exponent from a lane's tangent after a time `duration`; `log_norm0` = ln‖v_0‖.
template <int D, bool with_z>
double lyapunov_value_over(const double* v, double folds, double log_norm0, double duration) {
  double sum = 0.0;
  for (int k = 0; k < 2 * D + (with_z ? 1 : 0); ++k) sum = sum + v[k] * v[k];
  const double log_norm = 0.5 * std::log(sum);
  return (folds * kFoldLog + (log_norm - log_norm0)) / duration;
}

// The exponent from a lane's tangent after n steps of size h.
template <int D, bool with_z>
double lyapunov_value(const double* v, double folds, double log_norm0, std::int64_t n, double h) {
  if (n <= 0) return std::numeric_limits<double>::quiet_NaN();
  return lyapunov_value_over<D, with_z>(v, folds, log_norm0, static_cast<double>(n) * h);
}

// A lane's state as duals: values from x, derivative parts from the tangent.
template <Scene S>
LaneState<S::dof, Tangent> tangent_state(const LaneState<S::dof>& x, const LaneTangent<S::dof>& w) {
  constexpr int D = S::dof;
  LaneState<D, Tangent> y;
  for (int d = 0; d < D; ++d) {
    y.q[d] = {x.q[d], w.v[d]};
    y.p[d] = {x.p[d], w.v[D + d]};
    y.kq[d] = {x.kq[d], w.dkq[d]};
  }
  y.z = {x.z, tangent_has_z<S>() ? w.v[2 * D] : 0.0};
  y.mu = {x.mu, 0.0};
  y.lambda_numerator = {x.lambda_numerator, 0.0};
  y.lambda_denominator = {x.lambda_denominator, 0.0};
  y.lambda_folds = {x.lambda_folds, 0.0};
  y.broken = {x.broken, 0.0};
  y.t = {x.t, 0.0};
  return y;
}

// The force cache's tangent at a freshly loaded lane: the method's own start on duals.
template <Scene S, class Method>
void start_tangent(const LaneState<S::dof>& x, const ParamsOf<S, double>& c,
                   LaneTangent<S::dof>& w) {
  LaneState<S::dof, Tangent> y = tangent_state<S>(x, w);
  Method::template start<S>(y, c);
  for (int d = 0; d < S::dof; ++d) w.dkq[d] = y.kq[d].d;
}

// The starting tangent: 1 in each variable of `seed` (q.., p.., z: nonzero = chosen), 0
// elsewhere; ln‖v_0‖ = ln √k for k chosen variables. Equal components: no direction favoured.
template <Scene S, class Method>
LaneTangent<S::dof> seeded_tangent(const LaneState<S::dof>& x, const ParamsOf<S, double>& c,
                                   const std::vector<double>& seed) {
  LaneTangent<S::dof> w;
  for (int k = 0; k < 2 * S::dof + 1; ++k) w.v[k] = seed[static_cast<std::size_t>(k)];
  if (!tangent_has_z<S>()) w.v[2 * S::dof] = 0.0;
  start_tangent<S, Method>(x, c, w);
  return w;
}

// One lane's step with its tangent, in scalar code: the tile's lane body (tangent_tile.hpp) for
// one lane, the same step function on the same bits; for a lane stepped again to its stop
// (FormulaTracker::rerun) and for TangentLane. x.t is set by the caller; c and k as the
// tangent step takes them (coef_for_tangent).
template <Scene S, class Method, Carry carry, class K>
inline void step_with_tangent(LaneState<S::dof>& x, LaneTangent<S::dof>& w,
                              const ParamsOf<S, double>& c, const K& k) {
  constexpr int D = S::dof;
  LaneState<D, Tangent> y = tangent_state<S>(x, w);
  Method::template step<S, carry>(y, c, k);
  for (int d = 0; d < D; ++d) {
    x.q[d] = y.q[d].v, x.p[d] = y.p[d].v, x.kq[d] = y.kq[d].v;
    w.v[d] = y.q[d].d, w.v[D + d] = y.p[d].d, w.dkq[d] = y.kq[d].d;
  }
  x.z = y.z.v, x.mu = y.mu.v, x.broken = y.broken.v;
  x.lambda_numerator = y.lambda_numerator.v, x.lambda_denominator = y.lambda_denominator.v;
  if constexpr (tangent_has_z<S>()) w.v[2 * D] = y.z.d;
}

// The tile's fold of one lane's tangent (advance_with_tangent), in scalar code.
template <Scene S>
inline void fold_tangent(LaneTangent<S::dof>& w) {
  constexpr int N = 2 * S::dof + (tangent_has_z<S>() ? 1 : 0);
  double m = 0.0;
  for (int k = 0; k < N; ++k) m = std::fmax(m, std::fabs(w.v[k]));
  const double scale = fold_scale(m, w.folds);
  for (int k = 0; k < N; ++k) w.v[k] = w.v[k] * scale;
  for (int d = 0; d < S::dof; ++d) w.dkq[d] = w.dkq[d] * scale;
}

// ---- one lane: the facility the attractor table uses (attractor_lyapunov, issue 23) ----------

// One lane and its tangent, advanced a step at a time: the pieces of lane_lyapunov, for a caller
// that looks at the orbit between steps (engine/attractor_orbit.hpp). The lane's time is
// x.t at construction + n·h, n the steps taken since (never accumulated).
template <Scene S, class Method, Carry carry>
class TangentLane {
  // Without ln λ: the hybrid leap-frog's λ products would need the tile's folding.
  static_assert(!carry.mu, "TangentLane integrates no ln lambda");
  static constexpr int D = S::dof;

 public:
  // x with its force cache set by Method::start; the tangent starts as `seed` (seeded_tangent).
  TangentLane(LaneState<D>& x, const ParamsOf<S, double>& c, double h,
              const std::vector<double>& seed)
      : x_(x),
        h_(h),
        t0_(x.t),
        ct_(c),
        kt_(coef_for_tangent<Method>(Method::template coefficients<S>(h, c, x))),
        w_(seeded_tangent<S, Method>(x, c, seed)) {}

  void step() {
    x_.t = t0_ + static_cast<double>(n_) * h_;
    step_with_tangent<S, Method, carry>(x_, w_, ct_, kt_);
    fold_tangent<S>(w_);
    ++n_;
    x_.t = t0_ + static_cast<double>(n_) * h_;
  }

  std::int64_t steps() const { return n_; }
  const LaneTangent<D>& tangent() const { return w_; }

  // The finite-time exponent over the steps taken; `log_norm0` = ln‖v_0‖.
  double exponent(double log_norm0) const {
    return lyapunov_value<D, tangent_has_z<S>()>(w_.v, w_.folds, log_norm0, n_, h_);
  }

 private:
  LaneState<D>& x_;
  double h_, t0_;
  ParamsOf<S, double> ct_;
  TangentCoef<Method> kt_;
  LaneTangent<D> w_;
  std::int64_t n_ = 0;
};

// The finite-time exponent of one lane started at x (its force cache set by Method::start) with
// tangent `seed`, over `steps` steps of h from time x.t; x is left at the end state. The same
// arithmetic as the tile's, lane by lane.
template <Scene S, class Method, Carry carry>
double lane_lyapunov(LaneState<S::dof>& x, const ParamsOf<S, double>& c, std::int64_t steps,
                     double h, const std::vector<double>& seed, double log_norm0) {
  TangentLane<S, Method, carry> lane(x, c, h, seed);
  for (std::int64_t n = 0; n < steps; ++n) lane.step();
  return lane.exponent(log_norm0);
}

}  // namespace cs
