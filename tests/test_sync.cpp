// The on-line synchronization measures against the same quantities computed afterwards, by
// other formulas, from a stored trajectory sampled every step.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "support/run_in_memory.hpp"

namespace cs {
namespace {

TEST(SyncMeasures, MatchValuesComputedFromTheStoredTrajectory) {
  auto r = test::run_in_memory(R"(
    [scene]
    name = "coupled_oscillators"
    [integrator]
    t_end = 60.0
    [grid]
    g = { values = [0.0, 0.3, 0.8] }
    [measures]
    sync = { window = [20.0, 50.0] }
    trajectory = { every = 1 })");
  const double h = 0.01, w1 = std::sqrt(1.2), w2 = std::sqrt(0.8);
  const std::size_t samples = 6001, n0 = 2000, n1 = 5000;
  for (std::size_t g = 0; g < 3; ++g) {
    const double* q1 = &r["traj_q1"][g * samples];
    const double* q2 = &r["traj_q2"][g * samples];
    const double* p1 = &r["traj_p1"][g * samples];
    const double* p2 = &r["traj_p2"][g * samples];
    // Phases from complex amplitudes, unwrapped the textbook way.
    std::complex<double> sum = 0.0;
    std::vector<double> th1, th2;
    for (std::size_t n = n0; n <= n1; ++n) {
      std::complex<double> u1(q1[n], -p1[n] / w1), u2(q2[n], -p2[n] / w2);
      sum += std::polar(1.0, std::arg(u1) - std::arg(u2));
      th1.push_back(std::arg(u1));
      th2.push_back(std::arg(u2));
    }
    auto unwrap = [](std::vector<double>& th) {
      for (std::size_t i = 1; i < th.size(); ++i)
        th[i] = th[i - 1] + std::remainder(th[i] - th[i - 1], 2 * std::numbers::pi);
    };
    unwrap(th1);
    unwrap(th2);
    double d1 = th1.back() - th1.front(), d2 = th2.back() - th2.front();
    double window = (n1 - n0) * h;
    SCOPED_TRACE("g index " + std::to_string(g));
    // Same samples, different formulas: agreement to round-off accumulated over 3000 terms.
    EXPECT_NEAR(r["sync_r"][g], std::abs(sum) / double(n1 - n0 + 1), 1e-10);
    EXPECT_NEAR(r["sync_phase_drift"][g], (d1 - d2) / window, 1e-10);
    EXPECT_NEAR(r["sync_freq_ratio"][g], d1 / d2, 1e-10);
    std::complex<double> u1(q1[n1], -p1[n1] / w1), u2(q2[n1], -p2[n1] / w2);
    EXPECT_NEAR(r["sync_amplitude"][g], std::min(std::abs(u1), std::abs(u2)), 1e-12);
  }
}

}  // namespace
}  // namespace cs
