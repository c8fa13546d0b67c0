// The range of variable `name` over the grid (its initial value and the axes that set it),
// widened by half its width, at least ½, on either side: the energy trap's box (BasinBox), the
// recurrence mapper's default box, the scale of the continuation's matching threshold.
#pragma once

#include <array>
#include <string>

#include "model/run_spec.hpp"

namespace cs {

std::array<double, 2> default_range(const RunSpec& spec, const std::string& name);

}  // namespace cs
