#include "engine/grid.hpp"

#include <algorithm>
#include <stdexcept>

namespace cs {
namespace {

template <class Info>
int index_of(const std::vector<Info>& list, const std::string& name) {
  auto it = std::find_if(list.begin(), list.end(), [&](const Info& x) { return x.name == name; });
  if (it == list.end()) throw std::logic_error("grid: unknown name " + name);
  return static_cast<int>(it - list.begin());
}

}  // namespace

Grid::Grid(const RunSpec& spec, const SceneInfo& scene) {
  for (const auto& p : scene.parameters) base_params_.push_back(spec.parameters.at(p.name));
  for (const auto& v : scene.variables) base_state_.push_back(spec.initial.at(v.name));
  std::int64_t stride = 1;
  for (auto axis = spec.axes.rbegin(); axis != spec.axes.rend(); ++axis) {
    int slot = axis->is_step_size  ? -1  // sets no parameter or variable: see RunPlan slices
               : axis->is_parameter ? index_of(scene.parameters, axis->target)
                                    : index_of(scene.variables, axis->target);
    axes_.push_back({&axis->values, axis->is_parameter, slot, stride});
    stride *= static_cast<std::int64_t>(axis->values.size());
    uniform_params_ = uniform_params_ && !axis->is_parameter;
  }
  size_ = stride;
}

}  // namespace cs
