// The translation units of kernels built at run time: a custom scene's header (formula/) and the
// one block-runner instantiation a run needs (method × carried state × parameter layout × the
// basin mappers it uses, engine/mappers/mapper_choice.hpp × an adaptive method's dense output
// where it samples inside steps), with a C entry point the program finds with dlsym. One instantiation, not all of them: the first
// build of a new K takes seconds, not the minutes the whole matrix would. The attractor orbit
// (for describing a basin map's attractors) is a kernel of its own, per scene and method, built
// only when a map's table needs it: in the runner's kernel it cost every run of a new K 10-20 %
// of its first run (dop853's: 5.2 s with it, 4.1 s without), and a built-in scene needs nothing
// else.
#pragma once

#include <string>

#include "engine/mappers/mapper_choice.hpp"
#include "numerics/lane_state.hpp"

namespace cs {

inline constexpr const char* kKernelEntry = "contactsweep_run_block";
// The orbit kernel's entry point: one attractor's orbit (engine/attractor_orbit.hpp).
inline constexpr const char* kOrbitEntry = "contactsweep_attractor_orbit";
// A C string constant each kernel exports: the cache key it was built for (kernel_cache.hpp).
inline constexpr const char* kKernelKeySymbol = "contactsweep_kernel_key";

// The run's observe and stop (formula/measure_formulas.hpp, measures_source): the C++ of a
// struct and its name, kMeasuresStruct followed by the SHA-256 of the text (sweep.cpp). A process
// that loads several kernels (the Python module) must not have two different formulas under one
// name: template instances over the struct (a step kernel's tables) are GNU unique symbols, which
// the loader merges across libraries even under RTLD_LOCAL. An empty source: none.
struct MeasuresCode {
  std::string source, struct_name;
};

struct KernelChoice {
  std::string method;  // a name from method_catalog()
  Carry carry;
  bool uniform_parameters;
  MeasuresCode measures = {};  // the run's observe and stop
  // The basin mappers the runs need (mappers_of): only those are compiled.
  MapperChoice mappers = kEveryMapper;
  // An adaptive method's dense output for samples inside steps (samples_inside_steps); true for
  // a fixed-step method, which has none to leave out (one kernel for its runs either way).
  bool dense_output = true;
};

// A built-in scene's header and struct for kernel_source: its generated header
// (physics/<name>.hpp, in the snapshot) and its CamelCase struct. Built-in scenes are compiled
// ahead of time for every method and carried state but the lyapunov measure's tangent, whose
// kernels are built at run time like those of scene.K (no extra instantiations in the binary).
struct SceneSource {
  std::string header;
  std::string struct_name;
};
SceneSource builtin_scene_source(const std::string& name);
inline constexpr const char* kMeasuresStruct = "RunMeasureFormulas";

// The complete source text. `scene_header` defines struct `scene_struct` in namespace cs.
std::string kernel_source(const std::string& scene_header, const std::string& scene_struct,
                          const KernelChoice& choice);

// A step kernel's complete source text (entry point kStepKernelEntry, engine/step_kernel.hpp):
// the step loop and per-lane functions the program's runner calls (runs_on_step_kernel), for
// every fixed-step method: the text, and so the kernel's key, names no method. With the energy
// trap's entries for a basin map that uses it (StepKernelTrap), and the run's measures as
// formulas where they are not empty (StepKernelFormulas).
std::string step_kernel_source(const std::string& scene_header, const std::string& scene_struct,
                               Carry carry, bool uniform_parameters, bool energy_trap,
                               const MeasuresCode& measures = {});

// The orbit kernel's complete source text (entry point kOrbitEntry).
std::string orbit_kernel_source(const std::string& scene_header, const std::string& scene_struct,
                                const std::string& method);

// `source` with the definition of kKernelKeySymbol holding `key` appended.
std::string with_kernel_key(const std::string& source, const std::string& key);

}  // namespace cs
