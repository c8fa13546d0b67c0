// Dormand–Prince 8(7) (DOP853, Hairer, Nørsett & Wanner, "Solving ODEs I", §II.10, and their
// code dop853.f) on the full contact vector field (numerics/contact_field.hpp): an explicit
// Runge–Kutta pair of order 8 with an embedded error estimate (the 5th- and 3rd-order
// differences of dop853.f), 12 force evaluations a step. Any scene; not geometric: H = λK
// drifts, by an amount the tolerances bound.
//
// Adaptive, lane by lane (`adaptive = true`; engine/lane_tile.hpp's advance_adaptive): each lane
// carries its own time t, the step h it tries next and whether its last attempt was rejected.
// One attempt per lane per pass of the tile: the lane's error norm
//   err = |h|·e5 / sqrt(n·(e5 + 0.01·e3)),  e_k = Σ_i (E_k·K)_i² / sk_i²,
//   sk_i = atol + rtol·max(|y_i|, |y_new,i|)
// over the n components it integrates (q, p, z, and ln λ where K_z is not constant: the run
// plan carries z and ln λ for an adaptive method whatever it writes, so that rtol bounds them
// too and a lane's steps do not depend on the outputs asked for); the attempt is
// accepted when err ≤ 1 and the next h follows dop853.f's controller (safe = 0.9, fac1 = 0.333,
// fac2 = 6, beta = 0: h_new = h / max(1/6, min(1/0.333, err^(1/8)/0.9)), no larger than h after
// a rejection; h / min(1/0.333, err^(1/8)/0.9) after one), the last step cut to land on t_end
// exactly (Hairer's 1.01 h rule), the run failed (breakdown) when h falls below t's rounding.
// A lane's sequence of steps depends on its own state alone: the same bits on any rank, thread
// or slot. The coefficients are those of dop853.f (as scipy's dop853_coefficients lists them).
//
// Samples between a lane's steps (trajectory, sync) come from the continuous extension of
// order 7 of its accepted step (numerics/dop853_dense.hpp, built from the 12 stage rates and
// four more evaluations, only for a step that holds a sample).
//
// `step` is one step of the 8th-order formula at the fixed h of Coef: what the attractor orbits,
// which step at the spec's h, use. The lyapunov measure's tangent runs in the adaptive steps'
// own stages (`stage` on duals, `advance_tangent`: engine/measures/tangent_tile.hpp's
// AdaptiveTangent), its error not controlled; at a stop inside a step it is read on the
// continuous extension on duals (numerics/dop853_dense.hpp with T = Dual<double>).
#pragma once

#include <cmath>
#include <type_traits>

#include "numerics/contact_field.hpp"
#include "numerics/lane_state.hpp"
#include "numerics/method_description.hpp"
#include "physics/partials.hpp"

namespace cs {

struct Dop853 {
  static constexpr MethodDescription description{
      .name = "dop853",
      .catalog_position = 7,
      .order = 8,
      .properties = "Dormand-Prince 8(7), adaptive per lane with rtol/atol; any scene; not "
                    "geometric: H drifts within the tolerances",
      .force_evaluations_per_step = 12,
      .documentation = "Fewest force evaluations for a given accuracy where the flow is smooth "
                       "(final error 1e-6 to 1e-12): each lane takes its own steps, large where "
                       "little happens; basin maps and final states. Not geometric.",
      .adaptive = true,
  };
  static constexpr bool adaptive = true;

  template <class T>
  struct Coef {
    T h;
  };

  // The controller's settings, the same for every lane of a run.
  struct Control {
    double rtol, atol, t_end, h_max;
  };

  template <Scene S>
  static Coef<double> coefficients(double h, const ParamsOf<S, double>&,
                                   const LaneState<S::dof>&) {
    return {h};
  }

  template <Scene S>
  static bool breaks_down(const Coef<double>&) {
    return false;
  }

  template <Scene S, class T, class C>
  static void start(LaneState<S::dof, T>&, const C&) {}

  // One step of the 8th-order formula at k.h.
  // c: the parameters in T, or as plain doubles (the tangent step's).
  template <Scene S, Carry carry, class T, class C>
  [[gnu::always_inline, gnu::flatten]] static void step(LaneState<S::dof, T>& x,
                                                        const C& c, const Coef<T>& k) {
    constexpr bool with_z = carry.z || S::z_feeds_back;
    constexpr bool with_mu = carry.mu && !S::kz_constant;
    using P = contact_field::Point<S::dof, T>;
    const P y0{x};
    P r[12];
    stages<S, with_z, with_mu>(y0, c, x.t, k.h, r);
    P y1 = y0;
    combine<kRowB, 12, S::dof, with_z, with_mu>(y1, y0, k.h, r);
    store<S, carry, with_z, with_mu>(x, y1, y0, k.h, r[0]);
  }

  // One attempt of the lane at time t with step h (see the header). Branch-free: a lane whose t
  // is t_end already attempts a step of 0 and keeps its state, time and h.
  template <Scene S, Carry carry>
  [[gnu::always_inline, gnu::flatten]] static void attempt(
      LaneState<S::dof>& x, const ParamsOf<S, double>& c, double& t, double& h,
      double& last_rejected, double& accepted, double& rejected, const Control& k) {
    using lane_math::select;
    constexpr int D = S::dof;
    constexpr bool with_z = carry.z || S::z_feeds_back;
    constexpr bool with_mu = carry.mu && !S::kz_constant;
    using P = contact_field::Point<D, double>;
    const double hs = step_to_try(t, h, k);
    P r[12];
    stages<S, with_z, with_mu>(P{x}, c, t, hs, r);
    conclude<S, carry>(x, t, h, last_rejected, accepted, rejected, k, r);
  }

  // The step the lane at t tries: h, or what is left to t_end when h would (nearly) reach it.
  [[gnu::always_inline]] static double step_to_try(double t, double h, const Control& k) {
    const bool last = (t + 1.01 * h) - k.t_end > 0.0;
    return lane_math::select(last, k.t_end - t, h);
  }

  // Stage i's rate from y0 at t with step hs, from the rates r[0 … i − 1] (the tile computes
  // the stages one at a time over all its lanes: engine/lane_tile.hpp). T = Dual<double>: the
  // stage with its tangent (engine/measures/tangent_tile.hpp's AdaptiveTangent), the value
  // parts the same operations as T = double; t and hs stay plain numbers, so the tangent is the
  // variational equation's stage at the step the state's error chose.
  template <int i, Scene S, bool with_z, bool with_mu, class T, class C>
  [[gnu::always_inline]] static contact_field::Point<S::dof, T> stage(
      const contact_field::Point<S::dof, T>& y0, const C& c, double t, double hs,
      const contact_field::Point<S::dof, T>* r) {
    if constexpr (i == 0) {
      return contact_field::rate<S, with_z, with_mu>(y0, c, constant<T>(t));
    } else {
      contact_field::Point<S::dof, T> y = y0;
      combine<i, i, S::dof, with_z, with_mu>(y, y0, hs, r);
      return contact_field::rate<S, with_z, with_mu>(
          y, c, constant<T>(lane_math::mul_add(hs, kC[i], t)));
    }
  }

  // The tangent at the end of an accepted step: v = v0 + hs·Σ_j b_j·dr_j, dr_j the stages'
  // tangent rates (the 8th-order formula on the variational equation; no error estimate of its
  // own: see AdaptiveTangent).
  template <int D, bool with_z>
  [[gnu::always_inline]] static void advance_tangent(contact_field::Point<D, double>& v,
                                                     const contact_field::Point<D, double>& v0,
                                                     double hs,
                                                     const contact_field::Point<D, double>* dr) {
    combine<kRowB, 12, D, with_z, false>(v, v0, hs, dr);
  }

  // The attempt from its 12 stage rates r: the new state, the error norm, accepted or not, the
  // next h (see the header).
  template <Scene S, Carry carry>
  [[gnu::always_inline]] static void conclude(LaneState<S::dof>& x, double& t, double& h,
                                              double& last_rejected, double& accepted,
                                              double& rejected, const Control& k,
                                              const contact_field::Point<S::dof, double>* r) {
    using lane_math::select;
    constexpr int D = S::dof;
    constexpr bool with_z = carry.z || S::z_feeds_back;
    constexpr bool with_mu = carry.mu && !S::kz_constant;
    using P = contact_field::Point<D, double>;
    const double left = k.t_end - t;
    const bool active = left > 0.0;
    const bool last = (t + 1.01 * h) - k.t_end > 0.0;
    const double hs = select(last, left, h);
    const P y0{x};
    P y1 = y0;
    combine<kRowB, 12, D, with_z, with_mu>(y1, y0, hs, r);
    // The error norm over the components it integrates (RunPlan carries z and ln λ).
    static_assert(carry.z && carry.mu, "an adaptive method's run carries z and ln lambda (RunPlan)");
    constexpr int n = 2 * D + 1 + (with_mu ? 1 : 0);
    double e5 = 0.0, e3 = 0.0;
    auto add = [&](double a, double b, auto m) __attribute__((always_inline)) {
      const double sk = lane_math::mul_add(k.rtol, max(std::fabs(a), std::fabs(b)), k.atol);
      const double d5 = dot<kRowE5, 12>(r, m) / sk, d3 = dot<kRowE3, 12>(r, m) / sk;
      e5 = lane_math::mul_add(d5, d5, e5);
      e3 = lane_math::mul_add(d3, d3, e3);
    };
    contact_field::unrolled<D>([&](auto i) __attribute__((always_inline)) {
      add(y0.q[i], y1.q[i], std::integral_constant<int, i>{});
      add(y0.p[i], y1.p[i], std::integral_constant<int, D + i>{});
    });
    add(y0.z, y1.z, std::integral_constant<int, 2 * D>{});
    if constexpr (with_mu) add(y0.mu, y1.mu, std::integral_constant<int, 2 * D + 1>{});
    double deno = lane_math::mul_add(0.01, e3, e5);
    deno = select(deno > 0.0, deno, 1.0);
    double err = hs * e5 / std::sqrt(deno * n);
    err = select(err == err, err, INFINITY);  // a non-finite attempt is rejected
    const bool accept = active & (err <= 1.0);
    // dop853.f: fac11 = err^expo1 with expo1 = 1/8 (beta = 0): three square roots, exact.
    const double fac11 = std::sqrt(std::sqrt(std::sqrt(err)));
    constexpr double facc1 = 1.0 / 0.333, facc2 = 1.0 / 6.0, safe = 0.9;
    const double fac = max(facc2, min(facc1, fac11 / safe));
    double h_accepted = hs / fac;
    h_accepted = select(last_rejected > 0.0, min(h_accepted, hs), h_accepted);
    h_accepted = min(h_accepted, k.h_max);
    const double h_rejected = hs / min(facc1, fac11 / safe);
    // Hairer's step-size underflow: 0.1·|h| ≤ |t|·uround.
    const bool underflow = active & (0.1 * std::fabs(hs) <= std::fabs(t) * 0x1p-52);
    LaneState<D> moved = x;
    store<S, carry, with_z, with_mu>(moved, y1, y0, hs, r[0]);
    for (int d = 0; d < D; ++d) {
      x.q[d] = select(accept, moved.q[d], x.q[d]);
      x.p[d] = select(accept, moved.p[d], x.p[d]);
    }
    if constexpr (with_z) x.z = select(accept, moved.z, x.z);
    if constexpr (carry.mu) x.mu = select(accept, moved.mu, x.mu);
    x.broken = select(underflow, 1.0, x.broken);
    t = select(accept, select(last, k.t_end, t + hs), t);
    h = select(active, select(accept, h_accepted, h_rejected), h);
    last_rejected = select(active, select(accept, 0.0, 1.0), last_rejected);
    accepted = accepted + select(accept, 1.0, 0.0);
    rejected = rejected + select(active & !accept, 1.0, 0.0);
  }

 private:
  // Branch-free min and max (a select: std::fmin is a library call, which blocks vectorising);
  // the second operand where the comparison fails (NaN).
  [[gnu::always_inline]] static double min(double a, double b) {
    return lane_math::select(a < b, a, b);
  }
  [[gnu::always_inline]] static double max(double a, double b) {
    return lane_math::select(a > b, a, b);
  }

  // dop853.f's nodes c_i, matrix a_ij (stages 1–12), weights b_i and error weights (scipy's
  // E5 and E3 = b − bhh), 30 digits each, read to the nearest double: rows 0–11 of kW are a's,
  // then b, E5 and E3.
  static constexpr double kC[12] = {0.0,
                                    0.526001519587677318785587544488e-01,
                                    0.789002279381515978178381316732e-01,
                                    0.118350341907227396726757197510,
                                    0.281649658092772603273242802490,
                                    0.333333333333333333333333333333,
                                    0.25,
                                    0.307692307692307692307692307692,
                                    0.651282051282051282051282051282,
                                    0.6,
                                    0.857142857142857142857142857142,
                                    1.0};
  static constexpr double kW[15][12] = {
      {},
      {5.26001519587677318785587544488e-2},
      {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2},
      {2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2},
      {2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1,
       9.24834003261792003115737966543e-1},
      {3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1,
       1.25467687566822425016691814123e-1},
      {3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1,
       6.02165389804559606850219397283e-2, -1.7578125e-2},
      {3.70920001185047927108779319836e-2, 0.0, 0.0, 1.70383925712239993810214054705e-1,
       1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
       8.27378916381402288758473766002e-3},
      {6.24110958716075717114429577812e-1, 0.0, 0.0, -3.36089262944694129406857109825,
       -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
       2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1},
      {4.77662536438264365890433908527e-1, 0.0, 0.0, -2.48811461997166764192642586468,
       -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
       1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
       -2.03312017085086261358222928593e-2},
      {-9.3714243008598732571704021658e-1, 0.0, 0.0, 5.18637242884406370830023853209,
       1.09143734899672957818500254654, -8.14978701074692612513997267357,
       -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
       2.49360555267965238987089396762, -3.0467644718982195003823669022},
      {2.27331014751653820792359768449, 0.0, 0.0, -1.05344954667372501984066689879e1,
       -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
       2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
       -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
       6.43392746015763530355970484046e-1},
      // b
      {
      5.42937341165687622380535766363e-2, 0.0, 0.0, 0.0, 0.0,
      4.45031289275240888144113950566,    1.89151789931450038304281599044,
      -5.8012039600105847814672114227,    3.1116436695781989440891606237e-1,
      -1.52160949662516078556178806805e-1, 2.01365400804030348374776537501e-1,
      4.47106157277725905176885569043e-2},
      // E5
      {
      0.1312004499419488073250102996e-1, 0.0, 0.0, 0.0, 0.0,
      -0.1225156446376204440720569753e1, -0.4957589496572501915214079952,
      0.1664377182454986536961530415e1,  -0.3503288487499736816886487290,
      0.3341791187130174790297318841,    0.8192320648511571246570742613e-1,
      -0.2235530786388629525884427845e-1},
      // E3 = b − bhh: bhh1 = 0.244094488188976377952755905512 (stage 1), bhh2 (stage 9),
      // bhh3 (stage 12)
      {5.42937341165687622380535766363e-2 - 0.244094488188976377952755905512, 0.0, 0.0, 0.0,
       0.0, 4.45031289275240888144113950566, 1.89151789931450038304281599044,
       -5.8012039600105847814672114227,
       3.1116436695781989440891606237e-1 - 0.733846688281611857341361741547,
       -1.52160949662516078556178806805e-1, 2.01365400804030348374776537501e-1,
       4.47106157277725905176885569043e-2 - 0.220588235294117647058823529412e-1},
  };
  static constexpr int kRowB = 12, kRowE5 = 13, kRowE3 = 14;

  // x as a T: a constant (derivative part 0) where T is a dual.
  template <class T>
  [[gnu::always_inline]] static T constant(double x) {
    if constexpr (std::is_same_v<T, double>) return x;
    else return T{x, 0.0};
  }

  // Component m of a point: q_0.., p_0.., z, ln λ.
  template <int m, int D, class T>
  [[gnu::always_inline]] static T& at(contact_field::Point<D, T>& y) {
    if constexpr (m < D) return y.q[m];
    else if constexpr (m < 2 * D) return y.p[m - D];
    else if constexpr (m == 2 * D) return y.z;
    else return y.mu;
  }
  template <int m, int D, class T>
  [[gnu::always_inline]] static const T& at(const contact_field::Point<D, T>& y) {
    return at<m>(const_cast<contact_field::Point<D, T>&>(y));
  }

  // Σ_j w_j·r_j (w: row `row` of kW), component m, over the j < J with w_j ≠ 0, fused in the
  // order of j.
  template <int row, int J, int D, class T, class M>
  [[gnu::always_inline]] static T dot(const contact_field::Point<D, T>* r, M) {
    constexpr int m = M::value;
    T s = kW[row][0] * at<m>(r[0]);
    contact_field::unrolled<J>([&](auto j) __attribute__((always_inline)) {
      if constexpr (j > 0 && kW[row][j] != 0.0) s = lane_math::mul_add(kW[row][j], at<m>(r[j]), s);
    });
    return s;
  }

  // y = y0 + h·Σ_j w_j·r_j on every integrated component.
  template <int row, int J, int D, bool with_z, bool with_mu, class T, class H>
  [[gnu::always_inline]] static void combine(contact_field::Point<D, T>& y,
                                             const contact_field::Point<D, T>& y0, H h,
                                             const contact_field::Point<D, T>* r) {
    contact_field::unrolled<2 * D + 2>([&](auto m) __attribute__((always_inline)) {
      constexpr bool integrated = m < 2 * D || (m == 2 * D && with_z) || (m == 2 * D + 1 && with_mu);
      if constexpr (integrated) at<m>(y) = lane_math::mul_add(h, dot<row, J>(r, m), at<m>(y0));
    });
  }

  // The 12 stage rates from y0 at time t with step h.
  template <Scene S, bool with_z, bool with_mu, class T, class C>
  [[gnu::always_inline]] static void stages(const contact_field::Point<S::dof, T>& y0,
                                            const C& c, T t, T h,
                                            contact_field::Point<S::dof, T>* r) {
    r[0] = contact_field::rate<S, with_z, with_mu>(y0, c, t);
    contact_field::unrolled<11>([&](auto i0) __attribute__((always_inline)) {
      constexpr int i = i0 + 1;
      contact_field::Point<S::dof, T> y = y0;
      combine<i, i, S::dof, with_z, with_mu>(y, y0, h, r);
      r[i] = contact_field::rate<S, with_z, with_mu>(y, c, lane_math::mul_add(h, T{} + kC[i], t));
    });
  }

  // The new state into x: q, p (z, ln λ where integrated); ln λ's exact increment −h·K_z where
  // K_z is constant (r0.mu = −K_z).
  template <Scene S, Carry carry, bool with_z, bool with_mu, class T>
  [[gnu::always_inline]] static void store(LaneState<S::dof, T>& x,
                                           const contact_field::Point<S::dof, T>& y1,
                                           const contact_field::Point<S::dof, T>&, T h,
                                           const contact_field::Point<S::dof, T>& r0) {
    for (int d = 0; d < S::dof; ++d) x.q[d] = y1.q[d], x.p[d] = y1.p[d];
    if constexpr (with_z) x.z = y1.z;
    if constexpr (with_mu) x.mu = y1.mu;
    else if constexpr (carry.mu) x.mu = x.mu + h * r0.mu;
  }
};

}  // namespace cs
