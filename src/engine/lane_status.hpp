// A lane's outcome, the value of its cell in `status`: its own header, so that the step loop's
// headers (engine/lane_health.hpp, in a step kernel's prelude) need nothing of the run's plan.
#pragma once

#include <cstdint>

namespace cs {

// A cell's `status`. The values only grow: 0–2 keep their meaning in every file.
//   diverged: q or p not finite, or beyond the scene's bound;
//   breakdown: a λ factor 1 ± (h/2)K_z reached ≤ 0;
//   non_finite: integrated to its end (or early stop), but a value written for it is not finite
//     where its dataset promises one (z, ln λ, H, trajectory or sync values);
//   undefined_at_start: K or one of its partials is not finite at the initial state: nothing
//     is integrated and every value is NaN.
enum class LaneStatus : std::uint8_t {
  ok = 0,
  diverged = 1,
  breakdown = 2,
  non_finite = 3,
  undefined_at_start = 4
};

}  // namespace cs
