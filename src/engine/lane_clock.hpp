// A lane's time and the integer of the runner's looks: what the block runner, its mappers and a
// step kernel's step loop with measures as formulas (engine/measures/formula_steps.hpp) count
// with.
#pragma once

#include <cstdint>

namespace cs {

// The integer type of the looks' per-lane flags and countdowns (BlockRunner::screen()). With
// AVX2 they are as wide as the doubles they come from, so the vector loop packs no 64-bit compare
// masks into 32-bit lanes: the looks' share of the 512² basin map went from 6.8 to 5.7 % (Zen 4,
// perf). AVX-512 compares into mask registers, which pack for free; there 64-bit flags only
// double the arrays (7.2–8.1 % against 6.7–7.3 %, four runs each). Only speed depends on it.
#ifdef __AVX512F__
using LookInt = std::int32_t;
#else
using LookInt = std::int64_t;
#endif

// A lane's time after n steps, computed as the kernel does (lane_tile.hpp).
struct LaneClock {
  double t_start = 0.0, h = 0.0;
  double at(std::int64_t n) const { return t_start + static_cast<double>(n) * h; }
};

}  // namespace cs
