// What the energy trap (energy_trap.hpp) keeps of a run's grid beyond the run's blocks, for the
// memory check before the run (parallel/sweep.cpp).
#pragma once

#include <cstdint>

#include "engine/mappers/mapper_choice.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// The combinations of the q axes' values the trap visits for E₀, the largest initial energy of
// the grid; beyond it E₀ is +∞ and the trap keeps no q values.
inline constexpr std::int64_t kEnergyTrapMostCombinations = std::int64_t{1} << 22;

// Bytes of q values the trap's record of the wells keeps for the process's lifetime: one copy
// of each q's values over the grid, shared by every parameter set of the grid, when their
// combinations are few enough to visit. A map without the trap keeps none.
inline double energy_trap_record_bytes(const RunPlan& plan) {
  if (plan.map.basin < 0 || !mappers_of(plan).trap) return 0.0;
  std::int64_t values = 0, combinations = 1;
  for (int d = 0; d < plan.scene.dof; ++d) {
    std::int64_t n = 1;  // a q the grid does not vary
    for (const auto& axis : plan.spec.axes)
      if (!axis.is_parameter && !axis.is_step_size && axis.target == plan.scene.variables[static_cast<std::size_t>(d)].name)
        n = static_cast<std::int64_t>(axis.values.size());
    values += n;
    combinations *= n;
    if (combinations > kEnergyTrapMostCombinations) return 0.0;
  }
  return static_cast<double>(values) * sizeof(double);
}

}  // namespace cs
