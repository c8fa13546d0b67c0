#include "engine/fixed_point_exponent.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "engine/run_plan.hpp"
#include "physics/builtin_scenes.hpp"  // generated from physics/scenes.toml
#include "physics/partials.hpp"

namespace cs {
namespace {

// The contact vector field in (q.., p.., z), z only where it feeds back, as the kernels'
// tangent carries it (tangent_has_z): where it does not, (q, p) move on their own and z's row
// would only add ∂z'/∂z = K_z, the rate of z, not of the motion.
template <Scene S>
struct ContactField {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D + (S::z_feeds_back ? 1 : 0);
  using Vector = std::array<double, N>;

  const ParamsOf<S, double>& c;
  double z0, t;

  Vector operator()(const Vector& x) const {
    double q[D], p[D];
    for (int d = 0; d < D; ++d) q[d] = x[d], p[d] = x[D + d];
    const double z = S::z_feeds_back ? x[2 * D] : z0;
    const double kz = K_z<S>(q, p, z, c, t);
    Vector f{};
    double p_kp = 0.0;
    for_each_dof<D>([&](auto i) {
      const double kp = K_p<S, i.value>(q, p, z, c, t);
      f[i.value] = kp;
      f[D + i.value] = -K_q<S, i.value>(q, p, z, c, t) + p[i.value] * kz;
      p_kp += p[i.value] * kp;
    });
    if constexpr (S::z_feeds_back) f[2 * D] = K<S>(q, p, z, c, t) - p_kp;
    return f;
  }
};

template <Scene S>
double exponent_of(const RunPlan& plan, const std::vector<double>& params,
                   const std::vector<double>& state) {
  using Field = ContactField<S>;
  constexpr int N = Field::N;
  const ParamsOf<S, double> c = S::params_from(params.data());
  const Field field{c, state[2 * S::dof], plan.spec.t_start};
  typename Field::Vector x{};
  for (int k = 0; k < N; ++k) x[k] = state[k];
  // Central differences of exact partials (dual numbers): an error of O(δ²) ≈ 1e-12 relative.
  Eigen::Matrix<double, N, N> jacobian;
  for (int j = 0; j < N; ++j) {
    const double delta = 1e-6 * (1.0 + std::fabs(x[j]));
    auto a = x, b = x;
    a[j] += delta, b[j] -= delta;
    const auto fa = field(a), fb = field(b);
    for (int i = 0; i < N; ++i) jacobian(i, j) = (fa[i] - fb[i]) / (2.0 * delta);
  }
  if (!jacobian.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::EigenSolver<Eigen::Matrix<double, N, N>> solver(jacobian, false);
  if (solver.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return solver.eigenvalues().real().maxCoeff();
}

template <class... Scenes>
double dispatch(const RunPlan& plan, const std::vector<double>& params,
                const std::vector<double>& state, SceneList<Scenes...>) {
  double out = 0.0;
  const bool found = ((plan.scene.name == Scenes::name
                           ? (out = exponent_of<Scenes>(plan, params, state), true)
                           : false) || ...);
  if (!found) throw std::logic_error("fixed_point_exponent: no built-in scene " + plan.scene.name);
  return out;
}

}  // namespace

double fixed_point_exponent(const RunPlan& plan, const std::vector<double>& params,
                            const std::vector<double>& state) {
  return dispatch(plan, params, state, BuiltinScenes{});
}

}  // namespace cs
