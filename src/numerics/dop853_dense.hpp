// DOP853's dense output (Hairer, Nørsett & Wanner, "Solving ODEs I", §II.6 and §II.10, and
// their dop853.f's CONTD8; the coefficients as scipy's dop853_coefficients lists them): the
// continuous extension of order 7 of one accepted step from (t0, y0) to (t0 + h, y1). It needs
// the rate at the step's end (stage 13, f(t0 + h, y1)) and three extra stages (at t0 + 0.1h,
// 0.2h, 7h/9), then
//   y(t0 + θh) = y0 + θ(F0 + (1−θ)(F1 + θ(F2 + (1−θ)(F3 + θ(F4 + (1−θ)(F5 + θF6))))))
// with F0 = y1 − y0, F1 = h f0 − F0, F2 = 2F0 − h(f1 + f0), F3… = h·Σ_j D_j f_j.
//
// Built only for a lane whose accepted step holds a sample time (engine/lane_tile.hpp): four
// more force evaluations for that step, none for the others. Computed from the lane's own step
// alone, in one scalar order: the same bits on any rank, thread or slot.
//
// A component the step does not integrate (ln λ where K_z is constant: exact increments
// −h·K_z) is linear in time, and interpolated linearly between y0 and y1.
#pragma once

#include <type_traits>

#include "numerics/contact_field.hpp"
#include "numerics/lane_math.hpp"

namespace cs {

// T = Dual<double>: the same extension of the state with its tangent (the lyapunov measure's
// tangent at a stop inside the step, engine/measures/tangent_tile.hpp), value parts the same
// operations as T = double.
template <Scene S, bool with_z, bool with_mu, class T = double>
struct Dop853Dense {
  static constexpr int D = S::dof;
  using P = contact_field::Point<D, T>;

  double t0 = 0.0, h = 0.0;
  P y0{}, y1{};
  P F[7]{};

  // From the accepted step's endpoints and its 12 stage rates r; c the lane's parameters.
  template <class C>
  static Dop853Dense build(const P& y0, const P& y1, const P* r, const C& c, double t0,
                           double h) {
    Dop853Dense d;
    d.t0 = t0, d.h = h, d.y0 = y0, d.y1 = y1;
    P k[16];
    for (int j = 0; j < 12; ++j) k[j] = r[j];
    k[12] = contact_field::rate<S, with_z, with_mu>(y1, c, as_t(t0 + h));
    for (int s = 13; s < 16; ++s) {
      P y = y0;
      each([&](auto m) __attribute__((always_inline)) {
        T acc{};
        for (int j = 0; j < s; ++j)
          if (kA[s - 13][j] != 0.0) acc = lane_math::mul_add(kA[s - 13][j], at<m>(k[j]), acc);
        at<m>(y) = lane_math::mul_add(h, acc, at<m>(y0));
      });
      k[s] = contact_field::rate<S, with_z, with_mu>(y, c,
                                                     as_t(lane_math::mul_add(h, kCx[s - 13], t0)));
    }
    each([&](auto m) __attribute__((always_inline)) {
      const T dy = at<m>(y1) - at<m>(y0);
      at<m>(d.F[0]) = dy;
      at<m>(d.F[1]) = lane_math::mul_add(h, at<m>(k[0]), -dy);
      at<m>(d.F[2]) = 2.0 * dy - h * (at<m>(k[12]) + at<m>(k[0]));
      for (int i = 0; i < 4; ++i) {
        T acc{};
        for (int j = 0; j < 16; ++j)
          if (kD[i][j] != 0.0) acc = lane_math::mul_add(kD[i][j], at<m>(k[j]), acc);
        at<m>(d.F[3 + i]) = h * acc;
      }
    });
    return d;
  }

  // The state at time t (t0 ≤ t ≤ t0 + h): the integrated components from the polynomial, the
  // others linearly; components neither integrated nor carried are y0's.
  P at_time(double t) const {
    const double x = (t - t0) / h, x1 = 1.0 - x;
    P y = y0;
    contact_field::unrolled<2 * D + 2>([&](auto m) __attribute__((always_inline)) {
      if constexpr (integrated(m)) {
        T v{};
        for (int i = 6; i >= 0; --i) v = (v + at<m>(F[i])) * ((6 - i) % 2 == 0 ? x : x1);
        at<m>(y) = v + at<m>(y0);
      } else {
        at<m>(y) = lane_math::mul_add(x, at<m>(y1) - at<m>(y0), at<m>(y0));
      }
    });
    return y;
  }

 private:
  static constexpr bool integrated(int m) {
    return m < 2 * D || (m == 2 * D && with_z) || (m == 2 * D + 1 && with_mu);
  }
  // f(m) for every integrated component m.
  template <class F>
  [[gnu::always_inline]] static void each(F&& f) {
    contact_field::unrolled<2 * D + 2>([&](auto m) __attribute__((always_inline)) {
      if constexpr (integrated(m)) f(m);
    });
  }
  // A time as T (a constant: derivative part 0 where T is a dual).
  static T as_t(double t) {
    if constexpr (std::is_same_v<T, double>) return t;
    else return T{t, 0.0};
  }
  template <int m>
  static T& at(P& y) {
    if constexpr (m < D) return y.q[m];
    else if constexpr (m < 2 * D) return y.p[m - D];
    else if constexpr (m == 2 * D) return y.z;
    else return y.mu;
  }
  template <int m>
  static T at(const P& y) {
    return at<m>(const_cast<P&>(y));
  }

  // Nodes of the extra stages 14–16 (13 is the step's end, c = 1).
  static constexpr double kCx[3] = {0.1, 0.2, 0.777777777777777777777777777778};
  // Their rows of a (stages 1–16 as columns, 0-based).
  static constexpr double kA[3][16] = {
      {5.61675022830479523392909219681e-2, 0.0, 0.0, 0.0, 0.0, 0.0,
       2.53500210216624811088794765333e-1, -2.46239037470802489917441475441e-1,
       -1.24191423263816360469010140626e-1, 1.5329179827876569731206322685e-1,
       8.20105229563468988491666602057e-3, 7.56789766054569976138603589584e-3, -8.298e-3},
      {3.18346481635021405060768473261e-2, 0.0, 0.0, 0.0, 0.0,
       2.83009096723667755288322961402e-2, 5.35419883074385676223797384372e-2,
       -5.49237485713909884646569340306e-2, 0.0, 0.0, -1.08347328697249322858509316994e-4,
       3.82571090835658412954920192323e-4, -3.40465008687404560802977114492e-4,
       1.41312443674632500278074618366e-1},
      {-4.28896301583791923408573538692e-1, 0.0, 0.0, 0.0, 0.0,
       -4.69762141536116384314449447206, 7.68342119606259904184240953878,
       4.06898981839711007970213554331, 3.56727187455281109270669543021e-1, 0.0, 0.0, 0.0,
       -1.39902416515901462129418009734e-3, 2.9475147891527723389556272149,
       -9.15095847217987001081870187138},
  };
  // The interpolant's coefficients F3 … F6 (dop853.f's d4 … d7 rows).
  static constexpr double kD[4][16] = {
      {-0.84289382761090128651353491142e+1, 0.0, 0.0, 0.0, 0.0,
       0.56671495351937776962531783590, -0.30689499459498916912797304727e+1,
       0.23846676565120698287728149680e+1, 0.21170345824450282767155149946e+1,
       -0.87139158377797299206789907490, 0.22404374302607882758541771650e+1,
       0.63157877876946881815570249290, -0.88990336451333310820698117400e-1,
       0.18148505520854727256656404962e+2, -0.91946323924783554000451984436e+1,
       -0.44360363875948939664310572000e+1},
      {0.10427508642579134603413151009e+2, 0.0, 0.0, 0.0, 0.0,
       0.24228349177525818288430175319e+3, 0.16520045171727028198505394887e+3,
       -0.37454675472269020279518312152e+3, -0.22113666853125306036270938578e+2,
       0.77334326684722638389603898808e+1, -0.30674084731089398182061213626e+2,
       -0.93321305264302278729567221706e+1, 0.15697238121770843886131091075e+2,
       -0.31139403219565177677282850411e+2, -0.93529243588444783865713862664e+1,
       0.35816841486394083752465898540e+2},
      {0.19985053242002433820987653617e+2, 0.0, 0.0, 0.0, 0.0,
       -0.38703730874935176555105901742e+3, -0.18917813819516756882830838328e+3,
       0.52780815920542364900561016686e+3, -0.11573902539959630126141871134e+2,
       0.68812326946963000169666922661e+1, -0.10006050966910838403183860980e+1,
       0.77771377980534432092869265740, -0.27782057523535084065932004339e+1,
       -0.60196695231264120758267380846e+2, 0.84320405506677161018159903784e+2,
       0.11992291136182789328035130030e+2},
      {-0.25693933462703749003312586129e+2, 0.0, 0.0, 0.0, 0.0,
       -0.15418974869023643374053993627e+3, -0.23152937917604549567536039109e+3,
       0.35763911791061412378285349910e+3, 0.93405324183624310003907691704e+2,
       -0.37458323136451633156875139351e+2, 0.10409964950896230045147246184e+3,
       0.29840293426660503123344363579e+2, -0.43533456590011143754432175058e+2,
       0.96324553959188282948394950600e+2, -0.39177261675615439165231486172e+2,
       -0.14972683625798562581422125276e+3},
  };
};

}  // namespace cs
