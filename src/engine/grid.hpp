// The grid of a run: which parameters and initial values each flattened point gets.
// Points are numbered row-major over the spec's axes (the first axis varies slowest).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "model/run_spec.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

class Grid {
 public:
  Grid(const RunSpec& spec, const SceneInfo& scene);

  std::int64_t size() const { return size_; }
  int parameter_count() const { return static_cast<int>(base_params_.size()); }
  int variable_count() const { return static_cast<int>(base_state_.size()); }

  // Scene parameters (catalog order) and initial state (catalog variable order: q.., p.., z,
  // lambda) of one point. Inline: kernels built at run time (kernel_build/) call it too.
  void point(std::int64_t index, double* params, double* state) const {
    std::copy(base_params_.begin(), base_params_.end(), params);
    std::copy(base_state_.begin(), base_state_.end(), state);
    for (const auto& axis : axes_) {
      if (axis.slot < 0) continue;
      auto n = static_cast<std::int64_t>(axis.values->size());
      double v = (*axis.values)[static_cast<std::size_t>((index / axis.stride) % n)];
      (axis.is_parameter ? params : state)[axis.slot] = v;
    }
  }

  // True when no axis is a scene parameter: every point shares base_parameters().
  bool uniform_parameters() const { return uniform_params_; }
  const std::vector<double>& base_parameters() const { return base_params_; }

 private:
  struct AxisTarget {
    const std::vector<double>* values;
    bool is_parameter;
    int slot;  // index into params or state
    std::int64_t stride;
  };
  std::vector<double> base_params_;
  std::vector<double> base_state_;
  std::vector<AxisTarget> axes_;
  std::int64_t size_ = 1;
  bool uniform_params_ = true;
};

}  // namespace cs
