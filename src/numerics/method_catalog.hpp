// Run-time description of the integrators, for spec validation and `contactsweep methods`: the
// descriptions in numerics/methods/ (MethodDescription), as plain data for the rest of the program.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace cs {

struct MethodInfo {
  std::string name;
  int order;
  std::string properties;        // one line for `contactsweep methods`
  std::vector<std::string> needs_split_parts;  // empty: works on any scene
  int force_evaluations_per_step;
  bool adaptive = false;  // error-controlled per lane: takes integrator.rtol and atol
};

const std::vector<MethodInfo>& method_catalog();
const MethodInfo* find_method(std::string_view name);

// The exact sub-flows `method` composes that a scene offering `offered` lacks (empty: the method
// runs on that scene). Specs naming such a pair are refused before anything runs.
std::vector<std::string> missing_split_parts(const MethodInfo& method,
                                             const std::vector<std::string>& offered);

}  // namespace cs
