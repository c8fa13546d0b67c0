// The basin mappers a plan uses (engine/mappers/mapper_choice.hpp), which a kernel built at run
// time is compiled with and no others: they follow from the spec's basin measure alone, and a
// mapper set compiled without one of them refuses the plan instead of mapping it wrongly.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "engine/mappers/mapper_set.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/double_well.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

MapperChoice used_by(const std::string& measures, const std::string& scene = "double_well") {
  const std::string text = "[scene]\nname = \"" + scene +
                           "\"\n[integrator]\nh = 0.01\nt_end = 10.0\n"
                           "[grid]\nq_0 = { from = -2.0, to = 2.0, n = 4 }\n[measures]\n" +
                           measures;
  const RunSpec spec = parse_run_spec(text, {}, "test spec");
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  return mappers_of(plan);
}

void expect_choice(MapperChoice got, MapperChoice want, const std::string& what) {
  EXPECT_EQ(got.anchors, want.anchors) << what;
  EXPECT_EQ(got.trap, want.trap) << what;
  EXPECT_EQ(got.strobe, want.strobe) << what;
  EXPECT_EQ(got.recur, want.recur) << what;
}

TEST(MapperChoice, NoBasinMapUsesNoMapper) {
  expect_choice(used_by("final_state = true\n"), {false, false, false, false}, "final_state");
  expect_choice(used_by("final_state = true\ntrajectory = { every = 10 }\n"),
                {false, false, false, false}, "trajectory");
}

TEST(MapperChoice, AutonomousMapUsesAnchorsAndTrap) {
  // The double well's wells are fixed points alone: no recurrences by default.
  expect_choice(used_by("basin = {}\n"), {true, true, false, false}, "basin = {}");
  expect_choice(used_by("basin = { exact_trap = false }\n"), {true, false, false, false},
                "exact_trap = false");
  expect_choice(used_by("basin = { recurrence = true }\n"), {true, true, false, true},
                "recurrence = true");
}

TEST(MapperChoice, StroboscopicMapUsesCyclesNotAnchors) {
  expect_choice(used_by("basin = { period = 5.0 }\n"), {false, true, true, false}, "period = 5");
}

TEST(MapperChoice, Covers) {
  EXPECT_TRUE(covers(kEveryMapper, {true, true, true, true}));
  EXPECT_TRUE(covers({true, true, false, false}, {true, false, false, false}));
  EXPECT_TRUE(covers({false, false, false, false}, {false, false, false, false}));
  EXPECT_FALSE(covers({true, false, true, true}, {false, true, false, false}));
  EXPECT_FALSE(covers({false, false, false, false}, {false, false, false, true}));
  const MapperChoice both = MapperChoice{true, false, false, false} | MapperChoice{false, false, true, false};
  expect_choice(both, {true, false, true, false}, "union");
}

// A set compiled without the mappers a plan uses refuses it; one without any serves a plan
// that maps nothing.
TEST(MapperChoice, SetWithoutThePlansMappersRefusesIt) {
  using Bare = MapperSet<DoubleWell, true, 64, MapperChoice{false, false, false, false}>;
  const auto plan_for = [](const std::string& measures) {
    const std::string text =
        "[scene]\nname = \"double_well\"\n[integrator]\nh = 0.01\nt_end = 10.0\n"
        "[grid]\nq_0 = { from = -2.0, to = 2.0, n = 4 }\n[measures]\n" + measures;
    return parse_run_spec(text, {}, "test spec");
  };
  const ParamsOf<DoubleWell, double> params{1.0, 0.1};
  const RunSpec mapping = plan_for("basin = {}\n");
  const RunPlan map_plan(mapping, *find_scene(mapping.scene), *find_method(mapping.method));
  EXPECT_THROW(Bare(map_plan, LaneClock{0.0, 0.01}, params), std::logic_error);
  const RunSpec plain = plan_for("final_state = true\n");
  const RunPlan plain_plan(plain, *find_scene(plain.scene), *find_method(plain.method));
  const Bare set(plain_plan, LaneClock{0.0, 0.01}, params);
  EXPECT_FALSE(set.flagging());
}

}  // namespace
}  // namespace cs
