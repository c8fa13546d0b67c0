// numpy.linspace, bit for bit: grid axes { from, to, n } (spec files) and tests.
#pragma once

#include <cstdint>
#include <vector>

namespace cs {

// numpy.linspace(from, to, n) (endpoint=True), bit for bit; empty for n <= 0.
// Relies on the project-wide -ffp-contract=off: a fused i * step + from would differ.
std::vector<double> linspace(double from, double to, std::int64_t n);

}  // namespace cs
