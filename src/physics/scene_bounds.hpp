// When a lane counts as diverged: a non-finite coordinate or one beyond kDivergenceBound.
// The paper's scenes stay within |q|, |p| < 10 from the paper's initial states; a lane past 1e6
// has left every basin and would soon overflow, so it is flagged and stops costing time.
#pragma once

#include <cmath>

namespace cs {

inline constexpr double kDivergenceBound = 1e6;

template <int Dof>
inline bool beyond_bound(const double* q, const double* p) {
  bool inside = true;
  for (int i = 0; i < Dof; ++i)
    inside = inside && std::fabs(q[i]) <= kDivergenceBound && std::fabs(p[i]) <= kDivergenceBound;
  return !inside;  // NaN fails every comparison, so it counts as diverged
}

}  // namespace cs
