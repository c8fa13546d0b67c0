// The Jacobian of K's contact vector field at a state (and the field there), from GiNaC's exact partial derivatives:
// q' = K_p, p' = −K_q + p K_z and, where z feeds back (KTraits::z_feeds_back), z' = K − p·K_p,
// differentiated symbolically by q.., p.. (and z), each entry the double nearest its exact value
// at the state (evaluated as K's constants are: k_constant.cpp). At a fixed point its largest
// real eigenvalue part is the flow's largest Lyapunov exponent (engine/fixed_point_exponent.hpp),
// with no finite-time or finite-difference error, the same for a built-in scene and for the same
// K written in the spec.
//
// Not thread-safe (GiNaC keeps global state): one thread at a time, as every use of K's formula.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace cs {

class ContactJacobian {
 public:
  // K as written and its parameters in the order values will come (a run's scene's order);
  // throws InputError where K does not parse.
  ContactJacobian(const std::string& k, const std::vector<std::string>& parameter_order);
  // The state's components it reads and differentiates by: 2·dof, and z where it feeds back.
  int size() const;
  int dof() const;
  // q' = K_p reads neither p nor z (a cotangent lift K = p·F(q)): the Jacobian's q rows vanish
  // identically in the p and z columns, so the q system is one of its own and its dof × dof
  // block holds its exponents; the rest are the adjoint's, the q system's negated.
  bool q_closed() const;
  // The size() × size() matrix, row-major, at q.., p.., z (state: at least 2·dof + 1 values)
  // and t; NaN entries where one is not real or finite there (a pole).
  std::vector<double> at(const std::vector<double>& parameters, const std::vector<double>& state,
                         double t) const;
  // The vector field itself there, (q.., p.., and z where it feeds back)', each component the
  // double nearest its exact value, NaN where it is not real or finite: whether the state is a
  // fixed point at all (engine/fixed_point_exponent.hpp).
  std::vector<double> field(const std::vector<double>& parameters, const std::vector<double>& state,
                            double t) const;

 private:
  struct Symbolic;
  std::shared_ptr<const Symbolic> symbolic_;
};

}  // namespace cs
