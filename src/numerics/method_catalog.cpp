#include "numerics/method_catalog.hpp"

#include <algorithm>

namespace cs {

namespace {

// Splitting methods compose exact flows of K = sum p^2/2 + V(q) + Z(z). The step solves both
// shapes of Z a scene can offer (z_linear, z_quadratic); the list cannot say "one of", so it
// names the parts every such scene must offer. (A function, not a global: no static init order.)
std::vector<std::string> split_parts() { return {"kinetic", "potential"}; }

}  // namespace

const std::vector<MethodInfo>& method_catalog() {
  static const std::vector<MethodInfo> catalog{
      {"hybrid_leapfrog", 2,
       "Sogo & Ohnishi's hybrid leap-frog (paper, sec. 3.1), explicit; (q, lambda p) conformally "
       "symplectic; H = lambda K drifts linearly",
       {}, 1},
      {"symmetric_leapfrog", 2,
       "contact variational integrator (Vermeeren, Bravetti, Seri 2019) with trapezoidal z = "
       "generalized Stormer-Verlet on lambda K; symmetric; H bounded; implicit in z where K_z "
       "depends on z (2 Newton steps)",
       {}, 1},
      {"contact_splitting2", 2,
       "Strang composition of the exact flows of p^2/2, V(q), Z(z) (Bravetti, Seri, Vermeeren, "
       "Zadra 2020); contact map; H bounded",
       split_parts(), 1},
      {"contact_splitting4", 4,
       "Yoshida triple jump of contact_splitting2 (3 stages); contact map; H bounded",
       split_parts(), 3},
      {"contact_splitting6", 6,
       "Yoshida's 7-stage solution A over contact_splitting2; contact map; H bounded",
       split_parts(), 7},
      {"rk4", 4,
       "classical Runge-Kutta on the full contact vector field; any scene; not geometric: H "
       "drifts slowly",
       {}, 4},
  };
  return catalog;
}

std::vector<std::string> missing_split_parts(const MethodInfo& method,
                                             const std::vector<std::string>& offered) {
  std::vector<std::string> missing;
  for (const std::string& part : method.needs_split_parts)
    if (std::find(offered.begin(), offered.end(), part) == offered.end()) missing.push_back(part);
  return missing;
}

const MethodInfo* find_method(std::string_view name) {
  const auto& all = method_catalog();
  auto it = std::find_if(all.begin(), all.end(), [&](const MethodInfo& m) { return m.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace cs
