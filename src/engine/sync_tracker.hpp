// On-line synchronization measures of two oscillators over a time window [n0, n1] (in steps),
// sampled every few steps (RunPlan::chunk, at most 0.2 time units apart). Phases
// θ_k = atan2(−p_k/ω_k, q_k) advance like ω_k t for a free oscillator; they are unwrapped sample
// by sample (0.2·ω ≪ π apart), which gives the mean frequencies and the drift of θ₁ − θ₂.
// e^{i(θ₁−θ₂)} for the phase-locking value needs no trig: it is the normalised product
// (q₁ − i p₁/ω₁)·conj(q₂ − i p₂/ω₂).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace cs {

struct SyncResult {
  double r, phase_drift, freq_ratio, amplitude;
};

class SyncTracker {
 public:
  // Feed the state at step n; returns true when n is the window's last step (result() is ready).
  // (q1, p1) and (q2, p2) are the two degrees of freedom compared.
  bool sample(std::int64_t n, std::int64_t n0, std::int64_t n1, double q1, double p1, double q2,
              double p2, double omega1, double omega2) {
    if (n < n0 || n > n1) return false;
    double x1 = q1, y1 = -p1 / omega1, x2 = q2, y2 = -p2 / omega2;
    double th1 = std::atan2(y1, x1), th2 = std::atan2(y2, x2);
    if (n == n0) {
      start1_ = unwrapped1_ = th1;
      start2_ = unwrapped2_ = th2;
    } else {
      unwrapped1_ += wrapped(th1 - last1_);
      unwrapped2_ += wrapped(th2 - last2_);
    }
    last1_ = th1;
    last2_ = th2;
    // e^{iθ₁}·e^{−iθ₂} = (x1 + i y1)(x2 − i y2) / (|u1||u2|)
    double a1 = std::hypot(x1, y1), a2 = std::hypot(x2, y2);
    double norm = a1 * a2;
    if (norm > 0.0) {
      sum_cos_ += (x1 * x2 + y1 * y2) / norm;
      sum_sin_ += (y1 * x2 - x1 * y2) / norm;
    }
    ++count_;
    amplitude_ = std::fmin(a1, a2);
    return n == n1;
  }

  SyncResult result(double window_length) const {
    double nan = std::numeric_limits<double>::quiet_NaN();
    if (count_ == 0) return {nan, nan, nan, nan};
    double d1 = unwrapped1_ - start1_, d2 = unwrapped2_ - start2_;
    return {std::hypot(sum_cos_, sum_sin_) / static_cast<double>(count_),
            (d1 - d2) / window_length, d2 != 0.0 ? d1 / d2 : nan, amplitude_};
  }

 private:
  static double wrapped(double d) {
    constexpr double pi = std::numbers::pi, two_pi = 2.0 * std::numbers::pi;
    if (d > pi) return d - two_pi;
    if (d <= -pi) return d + two_pi;
    return d;
  }

  double start1_ = 0, start2_ = 0, unwrapped1_ = 0, unwrapped2_ = 0, last1_ = 0, last2_ = 0;
  double sum_cos_ = 0, sum_sin_ = 0, amplitude_ = 0;
  std::int64_t count_ = 0;
};

}  // namespace cs
