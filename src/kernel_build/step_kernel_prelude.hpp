// Everything a step kernel (engine/step_kernel.hpp) includes but its scene: the step loop, every
// method, the scene's building blocks. Precompiled at build time like kernel_prelude.hpp, into
// step_kernel_prelude.hpp.gch beside the snapshot. It leaves out the block runner, the attractor
// orbits and the built-in scenes a whole kernel needs: 43 MB of precompiled state instead of
// 106, read by every step kernel's compile (0.23 -> 0.17 s for one method, Zen 4;
// docs/performance.md).
#pragma once

#include "engine/step_kernel_entry.hpp"
#include "numerics/method_list.hpp"
#include "physics/dual_math.hpp"
#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"
