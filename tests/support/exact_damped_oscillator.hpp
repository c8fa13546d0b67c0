// The exact flow of scene A, K = (p² + ω²q²)/2 − γz (shared/PHYSICS.md, re-derived):
// q'' + γq' + ω²q = 0 with Ω = √(ω² − γ²/4); λ = λ₀e^{γt}; H = λK is conserved, so
// K(t) = K₀e^{−γt} and z = (E − K)/γ with E = (p² + ω²q²)/2.
#pragma once

#include <cmath>

namespace cs::test {

struct ExactState {
  double q, p, z, log_lambda;
};

inline ExactState exact_damped_oscillator(double t, double omega, double gamma, double q0,
                                          double p0, double z0, double lambda0) {
  double w = std::sqrt(omega * omega - 0.25 * gamma * gamma);
  double decay = std::exp(-0.5 * gamma * t), c = std::cos(w * t), s = std::sin(w * t);
  ExactState x;
  x.q = decay * (q0 * c + (p0 + 0.5 * gamma * q0) / w * s);
  x.p = decay * (p0 * c - (omega * omega * q0 + 0.5 * gamma * p0) / w * s);
  double energy = 0.5 * (x.p * x.p + omega * omega * x.q * x.q);
  double k0 = 0.5 * (p0 * p0 + omega * omega * q0 * q0) - gamma * z0;
  x.z = (energy - k0 * std::exp(-gamma * t)) / gamma;
  x.log_lambda = std::log(lambda0) + gamma * t;
  return x;
}

}  // namespace cs::test
