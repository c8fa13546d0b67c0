// Every scene's K_q, K_p, K_z (derived from K by dual numbers) against central finite
// differences of K and against partials derived by hand, at random states.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/coupled_oscillators.hpp"
#include "physics/damped_oscillator.hpp"
#include "physics/double_well.hpp"
#include "physics/partials.hpp"
#include "physics/z2_damping.hpp"

namespace cs {
namespace {

// Parameters away from the paper's values so that no term vanishes by accident.
template <class S> ParamsOf<S, double> test_params();
template <> ParamsOf<DampedOscillator, double> test_params<DampedOscillator>() { return {1.3, 0.17}; }
template <> ParamsOf<Z2Damping, double> test_params<Z2Damping>() { return {0.9, 0.23}; }
template <> ParamsOf<DoubleWell, double> test_params<DoubleWell>() { return {1.2, 0.11}; }
template <> ParamsOf<CoupledOscillators, double> test_params<CoupledOscillators>() { return {1.2, 0.8, 0.7, 0.03}; }

// Hand-derived gradients: {K_q..., K_p..., K_z}.
template <class S> void hand_partials(const double* q, const double* p, double z, const ParamsOf<S, double>& c, double* g);
template <> void hand_partials<DampedOscillator>(const double* q, const double* p, double, const ParamsOf<DampedOscillator, double>& c, double* g) {
  g[0] = c.omega * c.omega * q[0]; g[1] = p[0]; g[2] = -c.gamma;
}
template <> void hand_partials<Z2Damping>(const double* q, const double* p, double z, const ParamsOf<Z2Damping, double>& c, double* g) {
  g[0] = c.omega * c.omega * q[0]; g[1] = p[0]; g[2] = -2.0 * c.gamma * z;
}
template <> void hand_partials<DoubleWell>(const double* q, const double* p, double, const ParamsOf<DoubleWell, double>& c, double* g) {
  g[0] = 2.0 * q[0] * (q[0] * q[0] - c.a * c.a); g[1] = p[0]; g[2] = -c.gamma;
}
template <> void hand_partials<CoupledOscillators>(const double* q, const double* p, double, const ParamsOf<CoupledOscillators, double>& c, double* g) {
  g[0] = c.omega1_sq * q[0] + 2.0 * c.g * q[0] * q[1] * q[1];
  g[1] = c.omega2_sq * q[1] + 2.0 * c.g * q[0] * q[0] * q[1];
  g[2] = p[0]; g[3] = p[1]; g[4] = -c.gamma;
}

template <class S>
class Partials : public ::testing::Test {};
using Scenes = ::testing::Types<DampedOscillator, Z2Damping, DoubleWell, CoupledOscillators>;
TYPED_TEST_SUITE(Partials, Scenes);

TYPED_TEST(Partials, MatchFiniteDifferencesAndHandDerivation) {
  using S = TypeParam;
  constexpr int D = S::dof;
  const auto c = test_params<S>();
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 100; ++trial) {
    double x[2 * D + 1];  // q..., p..., z
    for (double& v : x) v = u(rng);
    const double* q = x;
    const double* p = x + D;
    double z = x[2 * D];
    double derived[2 * D + 1];
    for_each_dof<D>([&](auto i) {
      derived[i] = K_q<S, i>(q, p, z, c);
      derived[D + i] = K_p<S, i>(q, p, z, c);
    });
    derived[2 * D] = K_z<S>(q, p, z, c);
    double hand[2 * D + 1];
    hand_partials<S>(q, p, z, c, hand);
    for (int k = 0; k < 2 * D + 1; ++k) {
      // Central difference: truncation error ≈ ε²K'''/6 (K is at most quartic, |K'''| < 100
      // here), round-off ≈ 1e-16·|K|/ε; ε = 1e-5 gives both below 1e-8.
      const double eps = 1e-5;
      double xp[2 * D + 1], xm[2 * D + 1];
      std::copy(x, x + 2 * D + 1, xp);
      std::copy(x, x + 2 * D + 1, xm);
      xp[k] += eps;
      xm[k] -= eps;
      double fd = (K<S>(xp, xp + D, xp[2 * D], c) - K<S>(xm, xm + D, xm[2 * D], c)) / (2 * eps);
      EXPECT_NEAR(derived[k], fd, 1e-8) << "variable " << k << " trial " << trial;
      // Same formula evaluated in another order: agreement to a few ulps of the terms.
      EXPECT_NEAR(derived[k], hand[k], 1e-13 * (1.0 + std::fabs(hand[k]))) << "variable " << k;
    }
  }
}

}  // namespace
}  // namespace cs
