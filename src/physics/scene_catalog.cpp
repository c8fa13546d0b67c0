#include "physics/scene_catalog.hpp"

#include <algorithm>

namespace cs {
namespace {

// Parameter order here is the order of each scene's Params (params_from) in its header.
std::vector<VariableInfo> one_dof_variables(double q0) {
  return {{"q", q0, "position"},
          {"p", 0.0, "momentum"},
          {"z", 1.0, "contact variable (minus the action)"},
          {"lambda", 1.0, "integration factor; H = lambda*K is conserved"}};
}

std::vector<SceneInfo> build_catalog() {
  const std::vector<std::string> split_linear{"kinetic", "potential", "z_linear"};
  return {
      {"damped_oscillator", "A", "K = (p^2 + omega^2 q^2)/2 - gamma z", 1,
       {{"omega", 1.0, "angular frequency"}, {"gamma", 0.1, "damping rate"}},
       one_dof_variables(1.0), {"final_state", "trajectory", "basin"}, split_linear, false, 0.01, 100.0},
      {"z2_damping", "B", "K = (p^2 + omega^2 q^2)/2 - gamma z^2", 1,
       {{"omega", 1.0, "angular frequency"}, {"gamma", 0.1, "damping coefficient of z^2"}},
       one_dof_variables(1.0), {"final_state", "trajectory", "basin"},
       {"kinetic", "potential", "z_quadratic"}, true, 0.01, 100.0},
      {"double_well", "C", "K = p^2/2 + (q^2 - a^2)^2/2 - gamma z", 1,
       {{"a", 1.0, "well position (minima at q = +-a)"}, {"gamma", 0.1, "damping rate"}},
       one_dof_variables(2.0), {"final_state", "trajectory", "basin"}, split_linear, false,
       0.01, 100.0, {LabelRule::Kind::sign_of_q1, "left_well", "right_well"}},
      {"coupled_oscillators", "D",
       "K = (p1^2 + omega1_sq q1^2)/2 + (p2^2 + omega2_sq q2^2)/2 + g q1^2 q2^2 - gamma z", 2,
       {{"omega1_sq", 1.2, "squared angular frequency of oscillator 1"},
        {"omega2_sq", 0.8, "squared angular frequency of oscillator 2"},
        {"g", 0.8, "coupling strength (the paper shows g = 0 and g = 0.8)"},
        {"gamma", 0.01, "damping rate"}},
       {{"q1", 1.0, "position of oscillator 1"},
        {"q2", -1.0, "position of oscillator 2"},
        {"p1", 0.0, "momentum of oscillator 1"},
        {"p2", 0.0, "momentum of oscillator 2"},
        {"z", 1.0, "contact variable (minus the action)"},
        {"lambda", 1.0, "integration factor; H = lambda*K is conserved"}},
       {"final_state", "trajectory", "basin", "sync"}, split_linear, false, 0.01, 200.0},
  };
}

}  // namespace

const std::vector<SceneInfo>& scene_catalog() {
  static const std::vector<SceneInfo> catalog = build_catalog();
  return catalog;
}

const SceneInfo* find_scene(std::string_view name) {
  const auto& all = scene_catalog();
  auto it = std::find_if(all.begin(), all.end(), [&](const SceneInfo& s) { return s.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace cs
