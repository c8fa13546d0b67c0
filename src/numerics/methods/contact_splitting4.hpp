// Yoshida's (1990) triple jump of the contact splitting base step S₂
// (numerics/contact_splitting.hpp): three S₂ of weights w₁, w₀, w₁, fourth order.
#pragma once

#include <array>

#include "numerics/contact_splitting.hpp"

namespace cs {

// w₁ = 1/(2 − 2^{1/3}), w₀ = −2^{1/3}·w₁, so w₀ + 2w₁ = 1.
struct YoshidaComposition4 {
  static constexpr double cbrt2 = 1.2599210498948731647672106072782283506;
  static constexpr double w1 = 1.0 / (2.0 - cbrt2);
  static constexpr double w0 = -cbrt2 * w1;
  static constexpr std::array<double, 3> weights{w1, w0, w1};
  static constexpr MethodDescription description{
      .name = "contact_splitting4",
      .catalog_position = 4,
      .order = 4,
      .properties = "Yoshida triple jump of contact_splitting2 (3 stages); contact map; H bounded",
      .needs_split_parts = kSplitFlowParts,
      .force_evaluations_per_step = 3,
      .documentation =
          "Has the smallest stability limit (h < 1.57 on scene A) and was never the "
          "cheapest in the work-precision runs: rk4 beats it at every tolerance, "
          "contact_splitting6 from 1e-4 down. Kept as the classical composition.",
  };
};

using ContactSplitting4 = ContactSplitting<YoshidaComposition4>;

}  // namespace cs
