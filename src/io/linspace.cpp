// numpy.linspace, bit for bit (linspace.hpp).
#include "io/linspace.hpp"

namespace cs {

std::vector<double> linspace(double from, double to, std::int64_t n) {
  if (n <= 0) return {};
  // numpy 1.24 function_base.linspace, step by step: y = arange(n) * step + from, with
  // y = arange(n) / div * delta where step underflows to 0, and the last point set to `to`.
  std::vector<double> y(static_cast<std::size_t>(n));
  const double delta = to - from;
  const std::int64_t div = n - 1;
  if (div == 0) {
    y[0] = 0.0 * delta + from;
    return y;
  }
  const double step = delta / static_cast<double>(div);
  for (std::int64_t i = 0; i < n; ++i) {
    const double index = static_cast<double>(i);
    const double offset = step == 0.0 ? index / static_cast<double>(div) * delta : index * step;
    y[static_cast<std::size_t>(i)] = offset + from;
  }
  y.back() = to;
  return y;
}

}  // namespace cs
