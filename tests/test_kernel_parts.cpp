// What a kernel built at run time compiles of the block runner, and no more: the basin mappers
// its plan uses (engine/mappers/mapper_choice.hpp), which follow from the spec's basin measure
// alone, and an adaptive method's dense output where its plan samples inside steps
// (samples_inside_steps). A runner compiled without a part its plan uses refuses the plan
// instead of running it wrongly; one without parts its plan does not use gives the same bits.
#include <bit>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/block_runner.hpp"
#include "engine/mappers/mapper_set.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "numerics/methods/dop853.hpp"
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

RunSpec well_spec(const std::string& measures) {
  return parse_run_spec("[scene]\nname = \"double_well\"\n[integrator]\nmethod = \"dop853\"\n"
                        "rtol = 1e-9\nt_end = 20.0\n"
                        "[grid]\nq_0 = { from = -2.0, to = 2.0, n = 6 }\n[measures]\n" + measures,
                        {}, "test spec");
}

TEST(DenseOutput, SamplesInsideStepsFollowTheMeasures) {
  const auto inside = [](const std::string& measures) {
    const RunSpec spec = well_spec(measures);
    return samples_inside_steps(RunPlan(spec, *find_scene(spec.scene), *find_method(spec.method)));
  };
  EXPECT_FALSE(inside("final_state = true\n"));
  EXPECT_FALSE(inside("final_state = true\nbasin = {}\n"));  // autonomous: looks, not samples
  EXPECT_TRUE(inside("trajectory = { every = 10 }\n"));
  EXPECT_TRUE(inside("basin = { period = 5.0 }\n"));  // the stroboscopic map's samples
}

// The runner of the built-in kernels (every mapper, the dense output) and the leanest one give
// the same final states bit for bit on a run that samples nothing inside steps; the lean one
// refuses a run with a trajectory.
TEST(DenseOutput, LeanRunnerHasTheBitsOfTheFullOne) {
  constexpr Carry carry{true, true, false};
  using Full = BlockRunner<DoubleWell, Dop853, carry, true>;
  using Lean = BlockRunner<DoubleWell, Dop853, carry, true, NoMeasureFormulas,
                           MapperChoice{false, false, false, false}, false>;
  const RunSpec spec = well_spec("final_state = true\n");
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  ASSERT_TRUE(plan.carry.z && plan.carry.mu && !plan.carry.tangent);
  BlockResults full({0, plan.grid.size()}, plan.columns), lean({0, plan.grid.size()}, plan.columns);
  Full(plan, full).run();
  Lean(plan, lean).run();
  ASSERT_EQ(full.columns.size(), lean.columns.size());
  for (std::size_t k = 0; k < full.columns.size(); ++k) {
    ASSERT_EQ(full.columns[k].size(), lean.columns[k].size());
    for (std::size_t i = 0; i < full.columns[k].size(); ++i)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(full.columns[k][i]),
                std::bit_cast<std::uint64_t>(lean.columns[k][i]))
          << plan.columns[k].dataset.name << "[" << i << "]";
  }
  const RunSpec sampled = well_spec("final_state = true\ntrajectory = { every = 10 }\n");
  const RunPlan sampled_plan(sampled, *find_scene(sampled.scene), *find_method(sampled.method));
  BlockResults out({0, sampled_plan.grid.size()}, sampled_plan.columns);
  EXPECT_THROW(Lean(sampled_plan, out), std::logic_error);
}

}  // namespace
}  // namespace cs
