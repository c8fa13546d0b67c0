// Everything a kernel built at run time includes but its scene (kernel_source.cpp puts this
// first): the engine, every method, every built-in scene. The build precompiles it with the
// kernels' own flags into kernel_prelude.hpp.gch beside the snapshot (src/CMakeLists.txt), so a
// new K's kernel parses only its scene and its entry points: 4.4 → 3.5 s of compiler CPU on the
// double well written as K (Zen 5). The compiler checks that the .gch fits its flags and version
// and reads this text instead where it does not, so the kernel's code is the same either way.
#pragma once

#include <memory>

#include "engine/attractor_orbit.hpp"
#include "engine/block_runner.hpp"
#include "engine/step_kernel_entry.hpp"
#include "numerics/method_list.hpp"
#include "physics/builtin_scenes.hpp"
#include "physics/dual_math.hpp"
#include "physics/scene_bounds.hpp"
#include "physics/scene_concept.hpp"
