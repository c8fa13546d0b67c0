// The translation unit of a kernel built at run time: a custom scene's header (formula/) and the
// one block-runner instantiation a run needs (method × carried state × parameter layout), with a
// C entry point the program finds with dlsym. One instantiation, not all of them: the first
// build of a new K takes seconds, not the minutes the whole matrix would.
#pragma once

#include <string>

#include "numerics/lane_state.hpp"

namespace cs {

inline constexpr const char* kKernelEntry = "contactsweep_run_block";

struct KernelChoice {
  std::string method;  // a name from method_catalog()
  Carry carry;
  bool uniform_parameters;
};

// The complete source text. `scene_header` defines struct `scene_struct` in namespace cs.
std::string kernel_source(const std::string& scene_header, const std::string& scene_struct,
                          const KernelChoice& choice);

}  // namespace cs
