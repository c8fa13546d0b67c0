// Finding a lane's attractor on line (BasinMode::found). A lane is looked at through samples of
// its phase-space point x = (q.., p..): at every look for an autonomous scene, at t_start + k·T
// (the stroboscopic map) for a forced one. It settles on a period-m cycle (m = 1: a fixed point)
// when every sample stays within the tolerance (max norm) of the sample m before it in a run of
// `dwell` samples measured against fixed anchors — the m samples that opened the run — not against
// the previous sample: a lane creeping past a saddle by less than the tolerance per sample would
// otherwise pass for settled. Angles are compared modulo their period.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "engine/run_plan.hpp"

namespace cs {

// x − a for a variable of period `period` (0: not an angle), folded into [−period/2, period/2].
inline double phase_difference(double x, double a, double period) {
  const double d = x - a;
  return period > 0.0 ? d - period * std::nearbyint(d / period) : d;
}

// An angle as stored in the attractor table: in [0, period).
inline double reduced_angle(double x, double period) {
  return period > 0.0 ? x - period * std::floor(x / period) : x;
}

template <int N>
double phase_distance(const double* x, const double* a, const AttractorSearch& search) {
  double d = 0.0;
  for (int j = 0; j < N; ++j)
    d = std::fmax(d, std::fabs(phase_difference(x[j], a[j], search.angle_period[j])));
  return d;
}

// The one point of a cycle that stands for it in the table, whichever point a lane met first:
// the smallest in lexicographic order, coordinates within the tolerance counting as equal.
template <int N>
bool precedes(const double* x, const double* y, double tolerance) {
  for (int j = 0; j < N; ++j)
    if (std::fabs(x[j] - y[j]) > tolerance) return x[j] < y[j];
  return false;
}

// The samples of one lane and, per candidate period m, the run that is under way.
template <int N>
class CycleTracker {
 public:
  static constexpr int kMaxPeriod = 8;  // BasinMeasure::kMaxPeriodLimit
  using Point = std::array<double, N>;

  // Feeds sample k (k = 0, 1, ... in order); returns the period m of the cycle the lane has
  // settled on, 0 if it has not.
  int feed(const Point& x, const AttractorSearch& search) {
    const std::int64_t k = samples_++;
    ring_[static_cast<std::size_t>(k % kMaxPeriod)] = x;
    for (int m = 1; m <= search.max_period; ++m) {
      Run& run = runs_[static_cast<std::size_t>(m - 1)];
      if (k < m - 1) continue;
      if (run.anchored && k >= run.start + m) {
        const Point& anchor = anchors_[offset(m) + static_cast<std::size_t>((k - run.start) % m)];
        if (phase_distance<N>(x.data(), anchor.data(), search) <= search.tolerance) {
          if (++run.matched >= search.dwell_samples) {
            settled_start_ = run.start;
            return shortest_period(m, search);
          }
          continue;
        }
      }
      // A new run: the last m samples become its anchors.
      run.anchored = true;
      run.start = k - m + 1;
      run.matched = 0;
      for (int r = 0; r < m; ++r)
        anchors_[offset(m) + static_cast<std::size_t>(r)] =
            ring_[static_cast<std::size_t>((run.start + r) % kMaxPeriod)];
    }
    return 0;
  }

  // A cycle of m samples may be one of a divisor d of m gone round m/d times: a fixed point
  // approached by samples that alternate about it passes for a 2-cycle before it does for a
  // fixed point. The last m samples (each within the tolerance of its anchor, so within two of
  // each other) decide.
  int shortest_period(int m, const AttractorSearch& search) const {
    for (int d = 1; d < m; ++d) {
      if (m % d != 0) continue;
      bool repeats = true;
      for (int j = 0; j + d < m && repeats; ++j)
        repeats = phase_distance<N>(sample_back(j).data(), sample_back(j + d).data(), search) <=
                  2.0 * search.tolerance;
      if (repeats) return d;
    }
    return m;
  }

  // The sample j before the last.
  const Point& sample_back(int j) const {
    return ring_[static_cast<std::size_t>((samples_ - 1 - j) % kMaxPeriod)];
  }

  // The sample that opened the run that settled.
  std::int64_t settled_start() const { return settled_start_; }

  // The cycle's point for the table (the last m samples hold the cycle), angles reduced.
  Point representative(int m, const AttractorSearch& search) const {
    Point best = sample_back(0);
    for (int r = 1; r < m; ++r) {
      const Point& x = sample_back(r);
      if (precedes<N>(reduced(x, search).data(), reduced(best, search).data(), search.tolerance))
        best = x;
    }
    return reduced(best, search);
  }

  static Point reduced(const Point& x, const AttractorSearch& search) {
    Point y;
    for (int j = 0; j < N; ++j) y[j] = reduced_angle(x[j], search.angle_period[j]);
    return y;
  }

 private:
  struct Run {
    bool anchored = false;
    std::int64_t start = 0;  // sample index of the first anchor
    int matched = 0;         // samples since start + m that matched their anchor
  };
  static constexpr std::size_t offset(int m) { return static_cast<std::size_t>(m * (m - 1) / 2); }

  std::int64_t samples_ = 0, settled_start_ = 0;
  std::array<Point, kMaxPeriod> ring_{};
  std::array<Run, kMaxPeriod> runs_{};
  std::array<Point, kMaxPeriod*(kMaxPeriod + 1) / 2> anchors_{};
};

}  // namespace cs
