// The attractor table's merging (engine/attractor_table.hpp): sightings of one period whose
// points lie within kLinkTolerances tolerances of a candidate join it; farther ones are
// attractors of their own. Hand-built candidates on both sides of that distance.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "engine/attractor_table.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

const char* kSpec = R"(
  [scene]
  name = "double_well"
  [grid]
  q_0 = { from = -2.0, to = 2.0, n = 4 }
  [measures]
  basin = { exact_trap = false }
)";

TEST(AttractorTable, SightingsJoinWithinTheLinkDistanceAndNotBeyondIt) {
  const RunSpec spec = parse_run_spec(kSpec, {}, "test spec");
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  const double link = kLinkTolerances * plan.attractors.tolerance;
  ASSERT_GT(link, 0.0);
  // {first lane, value along a continuation axis (none), period, q, p} per candidate. The
  // distances are 3/4 and 5/4 of the link distance: a factor of 4/3 from either side of it, far
  // beyond any rounding of the points' differences.
  const std::vector<double> records = {
      0.0, 0.0, 1.0, 1.0, 0.0,                  // A
      1.0, 0.0, 1.0, 1.0 + 0.75 * link, 0.0,    // within the link of A: A again
      2.0, 0.0, 1.0, -1.0, 0.0,                 // C
      3.0, 0.0, 1.0, -1.0 - 1.25 * link, 0.0,   // beyond the link of C: another attractor
  };
  const AttractorTable table = merge_candidates(plan, records);
  ASSERT_EQ(table.attractors.size(), 3u);
  // Sorted by (period, point); the joined attractor keeps the point where it was first seen.
  EXPECT_EQ(table.attractors[0].point[0], -1.0 - 1.25 * link);
  EXPECT_EQ(table.attractors[1].point[0], -1.0);
  EXPECT_EQ(table.attractors[2].point[0], 1.0);
  EXPECT_EQ(table.attractors[2].source, 0);
}

}  // namespace
}  // namespace cs
