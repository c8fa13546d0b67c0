// Yoshida's (1990) 7-stage sixth-order composition of the contact splitting base step S₂
// (numerics/contact_splitting.hpp).
#pragma once

#include <array>

#include "numerics/contact_splitting.hpp"

namespace cs {

// Solution A (his table 1, 15 digits as printed; the order conditions then hold to ~1e-15, far
// below what double precision can resolve in a step). Chosen over the 9-stage triple jump of the
// order-4 method: 7 instead of 9 force evaluations per step and a smaller leading error term.
struct YoshidaComposition6 {
  static constexpr double w1 = -1.17767998417887, w2 = 0.235573213359357, w3 = 0.784513610477560;
  static constexpr double w0 = 1.0 - 2.0 * (w1 + w2 + w3);
  static constexpr std::array<double, 7> weights{w3, w2, w1, w0, w1, w2, w3};
  static constexpr MethodDescription description{
      .name = "contact_splitting6",
      .catalog_position = 5,
      .order = 6,
      .properties = "Yoshida's 7-stage solution A over contact_splitting2; contact map; H bounded",
      .needs_split_parts = kSplitFlowParts,
      .force_evaluations_per_step = 7,
      .documentation =
          "For tight accuracy (1e-6 and below) or long runs: the cheapest there, "
          "with H bounded to 1e-11; at h = 0.1 a basin map with half the wrong "
          "cells of the hybrid leap-frog at h = 0.01, at the same cost.",
  };
};

using ContactSplitting6 = ContactSplitting<YoshidaComposition6>;

}  // namespace cs
