#include "engine/fixed_point_exponent.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>

#include "engine/run_plan.hpp"
#include "formula/contact_jacobian.hpp"

namespace cs {
namespace {

// K as written: the scene's description holds it as "K = <formula>", a built-in scene's (its
// catalog entry, from src/physics/scenes.toml) and a spec's alike.
std::string k_of(const RunPlan& plan) {
  const std::string& written = plan.scene.hamiltonian;
  const std::string prefix = "K = ";
  return written.rfind(prefix, 0) == 0 ? written.substr(prefix.size()) : written;
}

// Is `state` a fixed point, as far as the table can say? The table's point x̃ is a lane's
// sample, within the tolerance τ (max norm over q, p) of the fixed point x* it settled on: the
// anchor test settles a lane that stayed within τ of its anchor, so it sits within about τ of
// x*, and the energy trap's minima are exact. An RK method's step fixes x* exactly (every stage
// is x* where the field vanishes), and so does a splitting whose parts each vanish there: the
// lanes settle on x* itself, not beside it. Then f(x̃) = J(x*)(x̃ − x*) + O(|x̃ − x*|²), so
// ‖f(x̃)‖∞ ≤ ‖J‖∞·τ to first order; twice that allows for the second-order term and for J
// changing between x* and x̃ (both small against J over a tolerance: 10⁻³ by default). A point
// whose field is larger than that is none: the chatter of rk4 across the kink of
// V = q²/2 + 0.1|q| settles lanes at (1.2·10⁻⁴, −6.2·10⁻³), where |p'| = 0.097 against a bound
// of 3·10⁻³. A lane still creeping towards x* from further than about τ (a slow, overdamped
// approach) fails the rule too: it falls back to its orbit, the safe side. Over the (q, p) rows
// and columns alone: where z feeds back, the table holds no z (attractor_analysis.cpp takes the
// orbit there).
bool vanishes_within(const std::vector<double>& entries, const std::vector<double>& field, int n,
                     int dof, double tolerance) {
  const int qp = 2 * dof;
  double norm = 0.0, size = 0.0;
  for (int i = 0; i < qp; ++i) {
    double row = 0.0;
    for (int j = 0; j < qp; ++j) row += std::fabs(entries[static_cast<std::size_t>(i * n + j)]);
    norm = std::max(norm, row);
    size = std::max(size, std::fabs(field[static_cast<std::size_t>(i)]));
  }
  return size <= 2.0 * tolerance * norm;
}

}  // namespace

FixedPointLinearisation fixed_point_linearisation(const RunPlan& plan,
                                                  const std::vector<double>& params,
                                                  const std::vector<double>& state,
                                                  double tolerance) {
  FixedPointLinearisation out;
  // GiNaC keeps global state, and the attractors are described on several threads. One
  // Jacobian per K and parameter order, kept for the process (a map's attractors share it).
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::vector<std::string>>, ContactJacobian> known;
  std::vector<std::string> order;
  for (const auto& parameter : plan.scene.parameters) order.push_back(parameter.name);
  std::vector<double> entries, field;
  int n = 0, m = 0, dof = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    auto key = std::make_pair(k_of(plan), order);
    auto it = known.find(key);
    if (it == known.end()) it = known.emplace(key, ContactJacobian(key.first, order)).first;
    n = it->second.size();
    dof = it->second.dof();
    // A cotangent lift: the q system's block alone. The p rows carry its adjoint, whose
    // exponents are its own negated: at an attracting point of F they would be the largest and
    // positive (Lorenz at r = 10: +12.48 for −0.60). The orbit seeds q alone there too.
    m = it->second.q_closed() ? dof : n;
    entries = it->second.at(params, state, plan.spec.t_start);
    if (std::isfinite(tolerance)) field = it->second.field(params, state, plan.spec.t_start);
  }
  // The linearisation must exist at the point: an entry GiNaC cannot evaluate there (0/0 in
  // 2q³/√(q⁴), a kink's |q|/q) has no exponent to give, though the flow may have one.
  for (const double e : entries)
    if (!std::isfinite(e)) {
      out.undefined = true;
      return out;
    }
  Eigen::MatrixXd jacobian(m, m);
  double norm = 0.0;
  for (int i = 0; i < m; ++i) {
    double row = 0.0;
    for (int j = 0; j < m; ++j) {
      jacobian(i, j) = entries[static_cast<std::size_t>(i * n + j)];
      row += std::fabs(jacobian(i, j));
    }
    norm = std::max(norm, row);
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(jacobian, false);
  if (solver.info() != Eigen::Success) {
    out.undefined = true;
    return out;
  }
  out.norm = norm;
  for (const double f : field)
    if (!std::isfinite(f)) return out;
  if (std::isfinite(tolerance) && !vanishes_within(entries, field, n, dof, tolerance)) return out;
  out.lyapunov = solver.eigenvalues().real().maxCoeff();
  return out;
}

double fixed_point_exponent(const RunPlan& plan, const std::vector<double>& params,
                            const std::vector<double>& state, double tolerance) {
  return fixed_point_linearisation(plan, params, state, tolerance).lyapunov;
}

}  // namespace cs
