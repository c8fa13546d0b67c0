#include "engine/fixed_point_exponent.hpp"

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

}  // namespace

double fixed_point_exponent(const RunPlan& plan, const std::vector<double>& params,
                            const std::vector<double>& state) {
  // GiNaC keeps global state, and the attractors are described on several threads. One
  // Jacobian per K and parameter order, kept for the process (a map's attractors share it).
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::vector<std::string>>, ContactJacobian> known;
  std::vector<std::string> order;
  for (const auto& parameter : plan.scene.parameters) order.push_back(parameter.name);
  std::vector<double> entries;
  int n = 0, m = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    auto key = std::make_pair(k_of(plan), order);
    auto it = known.find(key);
    if (it == known.end()) it = known.emplace(key, ContactJacobian(key.first, order)).first;
    n = it->second.size();
    // A cotangent lift: the q system's block alone. The p rows carry its adjoint, whose
    // exponents are its own negated: at an attracting point of F they would be the largest and
    // positive (Lorenz at r = 10: +12.48 for −0.60). The orbit seeds q alone there too.
    m = it->second.q_closed() ? it->second.dof() : n;
    entries = it->second.at(params, state, plan.spec.t_start);
  }
  Eigen::MatrixXd jacobian(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) jacobian(i, j) = entries[static_cast<std::size_t>(i * n + j)];
  if (!jacobian.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(jacobian, false);
  if (solver.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return solver.eigenvalues().real().maxCoeff();
}

}  // namespace cs
