// The form of a run's K, for a built-in scene and for scene.K alike: what decides which basin
// mappers a map needs and which entries its kernel is built with.
#pragma once

#include "model/run_spec.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

// K = Σp²/2 + V(q) + k·z without t, the energy trap's form (physics/energy_wells.hpp): E =
// K(q, p, 0) changes as k·|p|², so with k < 0 every orbit ends where p = 0 and forces vanish
// (LaSalle), at fixed points, which the anchor test and the trap find.
bool energy_trap_form(const RunSpec& spec, const SceneInfo& scene);

// K reads the time t.
bool reads_time(const RunSpec& spec, const SceneInfo& scene);

}  // namespace cs
