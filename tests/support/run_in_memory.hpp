// Runs a spec through the engine without MPI or HDF5 and returns every dataset by name, as
// doubles in row-major grid order (times the trajectory length for traj_* datasets).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"

namespace cs::test {

using Datasets = std::map<std::string, std::vector<double>>;

// `block` > 0 cuts the grid into blocks of that many points (as ranks and threads would).
inline Datasets run_in_memory(const std::string& toml, const std::vector<std::string>& sets = {},
                              std::int64_t block = 0) {
  RunSpec spec = parse_run_spec(toml, sets, "test spec");
  RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  const std::int64_t n = plan.grid.size();
  if (block <= 0) block = n;
  Datasets out;
  for (std::int64_t b = 0; b < n; b += block) {
    BlockResults r({b, std::min(n, b + block)}, plan.columns);
    run_block(plan, r);
    for (std::size_t k = 0; k < plan.columns.size(); ++k) {
      auto& v = out[plan.columns[k].dataset.name];
      v.insert(v.end(), r.columns[k].begin(), r.columns[k].end());
    }
  }
  return out;
}

}  // namespace cs::test
