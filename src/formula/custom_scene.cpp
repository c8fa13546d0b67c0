#include "formula/custom_scene.hpp"

#include <fmt/core.h>

#include <cstdint>
#include <stdexcept>

#include "kernel_build/sha256.hpp"

namespace cs {
namespace {

std::vector<VariableInfo> variables_of(const KFormula& f) {
  std::vector<VariableInfo> vars;
  for (const auto& q : f.positions) vars.push_back({q, 0.0, "position " + q});
  for (const auto& p : f.momenta) vars.push_back({p, 0.0, "momentum " + p});
  vars.push_back({"z", 0.0, "contact variable (minus the action)"});
  vars.push_back({"lambda", 1.0, "integration factor; H = lambda*K is conserved where K has no t"});
  return vars;
}

std::vector<std::string> split_parts_of(const KTraits& traits) {
  if (!traits.z_part) return {};
  return {"kinetic", "potential", *traits.z_part == ZPart::linear ? "z_linear" : "z_quadratic"};
}

}  // namespace

std::shared_ptr<const CustomScene> make_custom_scene(const std::string& K,
                                                     const std::string& label) {
  auto scene = std::make_shared<CustomScene>();
  scene->formula = parse_k(K);
  const KFormula& f = scene->formula;
  SceneInfo& info = scene->info;
  info.name = label;
  info.hamiltonian = "K = " + K;
  info.dof = f.traits.dof;
  for (const auto& p : f.parameters) info.parameters.push_back({p, 0.0, "parameter of K"});
  info.variables = variables_of(f);
  info.measures = {"final_state", "trajectory", "basin", "lyapunov"};
  if (info.dof >= 2) info.measures.push_back("sync");  // of any two degrees of freedom
  info.split_parts = split_parts_of(f.traits);
  info.z_feeds_back = f.traits.z_feeds_back;
  info.default_h = 0.01;
  info.default_t_end = 100.0;
  // Named after K: a process that loads several kernels (the Python module, one per run) must
  // not have two different scenes under one name. Their template instances' static locals
  // (the energy trap's table of wells) are GNU unique symbols, which the loader merges across
  // libraries even under RTLD_LOCAL. One K, one header: sharing between its kernels is safe.
  // SHA-256: no K can be chosen to take another's name (kernel_build/sha256.hpp).
  scene->struct_name = "CustomScene" + sha256_hex(K, 32);
  try {
    scene->header = scene_header(f, scene->struct_name);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // as in parse_k: every failure on K is bad input
    throw InputError(std::string("scene.K: could not be analysed: ") + e.what());
  }
  return scene;
}

const SceneInfo& scene_of(const RunSpec& spec) {
  if (spec.custom) return spec.custom->info;
  const SceneInfo* scene = find_scene(spec.scene);
  if (scene == nullptr) throw std::logic_error("scene_of: no scene " + spec.scene);
  return *scene;
}

}  // namespace cs
