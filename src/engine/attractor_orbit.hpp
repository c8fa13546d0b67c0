// The orbit of one attractor's lane, in the run-time kernel (attractor_analysis.hpp asks for
// it): a transient, then a measuring window on which the tangent of the method's own step gives
// λ₁ (tangent_lyapunov.hpp's TangentLane), samples are taken, and an autonomous orbit's first
// return to its start is timed; a periodic orbit is then sampled again over one period.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/attractor_analysis.hpp"
#include "engine/attractor_search.hpp"
#include "engine/attractor_table.hpp"
#include "engine/measures/tangent_lyapunov.hpp"

namespace cs {

namespace attractor_orbit_detail {

template <int D>
double distance(const LaneState<D>& x, const double* a, const OrbitRequest& r) {
  double d = 0.0;
  for (int k = 0; k < 2 * D; ++k)
    d = std::fmax(d, std::fabs(phase_difference(k < D ? x.q[k] : x.p[k - D], a[k],
                                                r.angle_period[static_cast<std::size_t>(k)])));
  return d;
}

template <int D>
void put(const LaneState<D>& x, double* out) {
  for (int d = 0; d < D; ++d) out[d] = x.q[d], out[D + d] = x.p[d];
}

template <Scene S, int D>
bool sound(const LaneState<D>& x) {
  for (int d = 0; d < D; ++d)
    if (!std::isfinite(x.q[d]) || !std::isfinite(x.p[d])) return false;
  return x.broken == 0.0 && !S::diverged(x.q, x.p);
}

// Does the q motion close on itself? A tangent started in p alone leaves δq exactly 0 when no
// operation of the step that updates q reads p or z (dual derivatives of constants are exact
// zeros): a few steps from x, which is left unchanged.
template <Scene S, class Method, Carry carry>
bool q_closes(const LaneState<S::dof>& x, const ParamsOf<S, double>& c, double h) {
  constexpr int D = S::dof;
  std::vector<double> seed(2 * D + 1, 0.0);
  for (int d = 0; d < D; ++d) seed[static_cast<std::size_t>(D + d)] = 1.0;
  if (tangent_has_z<S>()) seed[2 * D] = 1.0;
  LaneState<D> y = x;
  TangentLane<S, Method, carry> lane(y, c, h, seed);
  for (int n = 0; n < 4; ++n) {
    lane.step();
    for (int d = 0; d < D; ++d)
      if (lane.tangent().v[d] != 0.0) return false;
  }
  return true;
}

}  // namespace attractor_orbit_detail

template <Scene S, class Method>
void attractor_orbit(const OrbitRequest& r, AttractorOrbit& out) {
  namespace detail = attractor_orbit_detail;
  constexpr int D = S::dof;
  constexpr Carry carry{S::z_feeds_back, false, false};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto c = S::params_from(r.params.data());
  LaneState<D> x{};
  for (int d = 0; d < D; ++d)
    x.q[d] = r.state[static_cast<std::size_t>(d)],
    x.p[d] = r.state[static_cast<std::size_t>(D + d)];
  x.z = r.state[2 * D];
  x.mu = 0.0;
  x.lambda_numerator = x.lambda_denominator = 1.0;
  x.t = r.t_start;
  Method::template start<S>(x, c);
  std::vector<double> seed = r.seed;
  double log_norm0 = r.log_norm0;
  if (r.seed_q_where_closed && detail::q_closes<S, Method, carry>(x, c, r.h)) {
    std::fill(seed.begin(), seed.end(), 0.0);
    for (int d = 0; d < D; ++d) seed[static_cast<std::size_t>(d)] = 1.0;
    log_norm0 = 0.5 * std::log(static_cast<double>(D));
  }
  out.points.assign(static_cast<std::size_t>(r.samples) * 2 * D, nan);
  out.lyapunov = out.return_time = nan;
  out.stroboscopic_return = 0;
  out.moved = false;
  out.finite = false;
  {
    TangentLane<S, Method, carry> transient(x, c, r.h, seed);
    for (std::int64_t n = 0; n < r.transient_steps; ++n) {
      transient.step();
      if (!detail::sound<S>(x)) return;
    }
  }
  const LaneState<D> start = x;
  double x0[2 * D], v0[2 * D], g[3] = {0.0, 0.0, 0.0};
  detail::put(x, x0);
  bool left = false;
  TangentLane<S, Method, carry> lane(x, c, r.h, seed);
  for (std::int64_t n = 0; n < r.window_steps; ++n) {
    if (n % r.sample_steps == 0 && n / r.sample_steps < r.samples) {
      const auto k = n / r.sample_steps;
      double* sample = &out.points[static_cast<std::size_t>(k) * 2 * D];
      detail::put(x, sample);
      const double d = detail::distance(x, out.points.data(), r);
      out.moved = out.moved || d > r.tolerance;
      if (r.stroboscopic && k > 0 && out.stroboscopic_return == 0 && d <= r.tolerance)
        out.stroboscopic_return = static_cast<int>(k);
    }
    lane.step();
    if (!detail::sound<S>(x)) return;
    if (r.stroboscopic || !std::isnan(out.return_time)) continue;
    // The first return: g = (x − x0)·v0, v0 the first step's displacement, crosses from below
    // to above 0 after the orbit has left the start's neighbourhood, near the start; the time of
    // the crossing from the parabola through the last three g (error O(h³)).
    double now[2 * D];
    detail::put(x, now);
    double gn = 0.0;
    for (int k = 0; k < 2 * D; ++k) {
      const double dk =
          phase_difference(now[k], x0[k], r.angle_period[static_cast<std::size_t>(k)]);
      if (n == 0) v0[k] = dk;
      gn += dk * v0[k];
    }
    g[0] = g[1], g[1] = g[2], g[2] = gn;
    double step_length = 0.0;
    for (int k = 0; k < 2 * D; ++k) step_length = std::fmax(step_length, std::fabs(v0[k]));
    const double near = kLinkTolerances * r.tolerance + step_length;
    const double d = detail::distance(x, x0, r);
    left = left || d > 2.0 * near;
    if (left && n >= 2 && g[1] < 0.0 && g[2] >= 0.0 && d <= near) {
      // g(s) through s = −1, 0, 1 (steps n−1, n, n+1 counted from the window's start, so the
      // step just taken ends at s = 1): the root in (0, 1].
      const double a = 0.5 * (g[2] + g[0]) - g[1], b = 0.5 * (g[2] - g[0]), cc = g[1];
      double s = -cc / b;  // linear fallback
      if (a != 0.0) {
        const double disc = std::sqrt(std::fmax(b * b - 4.0 * a * cc, 0.0));
        const double s1 = (-b + disc) / (2.0 * a), s2 = (-b - disc) / (2.0 * a);
        s = (s1 >= 0.0 && s1 <= 1.0) ? s1 : s2;
      }
      out.return_time = (static_cast<double>(n) + s) * r.h;
    }
  }
  out.lyapunov = lane.exponent(log_norm0);
  out.finite = true;
  if (r.stroboscopic || std::isnan(out.return_time) || !out.moved) return;
  // A periodic orbit: the samples again, over one period from the window's start, at the steps
  // nearest to k·T/K.
  x = start;
  TangentLane<S, Method, carry> cycle(x, c, r.h, seed);
  for (int k = 0; k < r.samples; ++k) {
    const auto at =
        static_cast<std::int64_t>(std::llround(out.return_time * k / (r.samples * r.h)));
    while (cycle.steps() < at) cycle.step();
    detail::put(x, &out.points[static_cast<std::size_t>(k) * 2 * D]);
  }
}

}  // namespace cs
