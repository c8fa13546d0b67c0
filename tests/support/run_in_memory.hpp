// Runs a spec through the engine without MPI or HDF5 and returns every dataset by name, as
// doubles in row-major grid order (times the trajectory length for traj_* datasets). Basin
// labels are the attractor table's, as a run writes them (parallel/basin_summary.cpp).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/attractor_table.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"

namespace cs::test {

using Datasets = std::map<std::string, std::vector<double>>;

// `block` > 0 cuts the grid into blocks of that many points (as ranks and threads would).
inline Datasets run_in_memory(const std::string& toml, const std::vector<std::string>& sets = {},
                              std::int64_t block = 0) {
  RunSpec spec = parse_run_spec(toml, sets, "test spec");
  std::vector<std::unique_ptr<RunSpec>> slice_specs;
  auto slices =
      step_size_slices(spec, *find_scene(spec.scene), *find_method(spec.method), slice_specs);
  Datasets out;
  for (const auto& plan : slices) {
    const std::int64_t begin = plan->point_offset, end = begin + plan->grid.size();
    const std::int64_t size = block > 0 ? block : end - begin;
    std::vector<BlockResults> blocks;
    for (std::int64_t b = begin; b < end; b += size) {
      blocks.emplace_back(PointRange{b, std::min(end, b + size)}, plan->columns);
      run_block(*plan, blocks.back());
    }
    if (plan->map.basin >= 0) {
      std::vector<double> candidates;
      for (const auto& r : blocks) {
        const std::vector<double> c = block_candidates(*plan, r);
        candidates.insert(candidates.end(), c.begin(), c.end());
      }
      const AttractorTable table = merge_candidates(*plan, candidates);
      for (auto& r : blocks) label_block(*plan, table.attractors, r, table.along);
    }
    for (const auto& r : blocks)
      for (std::size_t k = 0; k < plan->columns.size(); ++k) {
        auto& v = out[plan->columns[k].dataset.name];
        v.insert(v.end(), r.columns[k].begin(), r.columns[k].end());
      }
  }
  return out;
}

}  // namespace cs::test
