// What a kernel built at run time compiles of the block runner, and no more: the basin mappers
// its plan uses (engine/mappers/mapper_choice.hpp), which follow from the spec's basin measure
// alone, and an adaptive method's dense output where its plan samples inside steps
// (samples_inside_steps). A runner compiled without a part its plan uses refuses the plan
// instead of running it wrongly; one without parts its plan does not use gives the same bits.
#include <algorithm>
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
#include "numerics/methods/hybrid_leapfrog.hpp"
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

RunSpec well_spec(const std::string& measures, const std::string& method = "dop853") {
  return parse_run_spec("[scene]\nname = \"double_well\"\ngamma = 0.5\n[integrator]\nmethod = \"" + method +
                            "\"\n" + (method == "dop853" ? "rtol = 1e-9\n" : "") +
                            "t_end = 60.0\n[grid]\nq_0 = { from = -2.0, to = 2.0, n = 6 }\n"
                            "p_0 = { from = -1.5, to = 1.5, n = 4 }\n[measures]\n" + measures,
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

// Every column of a block, bit for bit, from the runner of the built-in kernels (every mapper,
// the dense output) and from `Lean`, compiled with exactly what the plan uses (as a kernel built
// at run time is): final states, basin labels, settlement records, settle times, trap verdicts,
// recurrence records and reasons.
template <class Method, Carry carry, MapperChoice used, bool dense>
void expect_lean_has_the_bits_of_full(const std::string& measures, const std::string& method) {
  using Full = BlockRunner<DoubleWell, Method, carry, true>;
  using Lean = BlockRunner<DoubleWell, Method, carry, true, NoMeasureFormulas, used, dense>;
  const RunSpec spec = well_spec(measures, method);
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  ASSERT_EQ(plan.carry.z, carry.z) << measures;
  ASSERT_EQ(plan.carry.mu, carry.mu) << measures;
  const MapperChoice u = mappers_of(plan);
  ASSERT_TRUE(u.anchors == used.anchors && u.trap == used.trap && u.strobe == used.strobe &&
              u.recur == used.recur) << measures;
  if constexpr (adaptive_method<Method>()) {
    ASSERT_EQ(samples_inside_steps(plan), dense) << measures;
  }
  BlockResults full({0, plan.grid.size()}, plan.columns), lean({0, plan.grid.size()}, plan.columns);
  Full(plan, full).run();
  Lean(plan, lean).run();
  ASSERT_EQ(full.columns.size(), lean.columns.size());
  for (std::size_t k = 0; k < full.columns.size(); ++k) {
    ASSERT_EQ(full.columns[k].size(), lean.columns[k].size());
    for (std::size_t i = 0; i < full.columns[k].size(); ++i)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(full.columns[k][i]),
                std::bit_cast<std::uint64_t>(lean.columns[k][i]))
          << measures << ": " << plan.columns[k].dataset.name << "[" << i << "]";
  }
  if (plan.map.basin >= 0) {  // lanes settled, so the mappers had work to do
    const auto& basin = full.columns[static_cast<std::size_t>(plan.map.basin)];
    EXPECT_GT(std::count_if(basin.begin(), basin.end(), [](double v) { return v != 0.0; }), 0)
        << measures;
  }
}

// The leanest dop853 runner (no mapper, no dense output) on final states alone; it refuses a
// plan with a trajectory, which samples inside steps.
TEST(DenseOutput, LeanRunnerHasTheBitsOfTheFullOne) {
  constexpr MapperChoice none{false, false, false, false};
  expect_lean_has_the_bits_of_full<Dop853, Carry{true, true, false}, none, false>(
      "final_state = true\n", "dop853");
  using Lean = BlockRunner<DoubleWell, Dop853, Carry{true, true, false}, true, NoMeasureFormulas,
                           none, false>;
  const RunSpec sampled = well_spec("final_state = true\ntrajectory = { every = 10 }\n");
  const RunPlan sampled_plan(sampled, *find_scene(sampled.scene), *find_method(sampled.method));
  BlockResults out({0, sampled_plan.grid.size()}, sampled_plan.columns);
  EXPECT_THROW(Lean(sampled_plan, out), std::logic_error);
}

// Basin maps: each runner compiled with its plan's mappers alone maps as the full one does.
TEST(MapperChoice, LeanRunnersMapAsTheFullOne) {
  constexpr Carry qp{false, false, false};
  expect_lean_has_the_bits_of_full<HybridLeapfrog, qp, MapperChoice{true, true, false, false},
                                   true>("basin = { early_stop = false }\n", "hybrid_leapfrog");
  expect_lean_has_the_bits_of_full<HybridLeapfrog, qp, MapperChoice{true, false, false, false},
                                   true>("basin = { exact_trap = false }\n", "hybrid_leapfrog");
  expect_lean_has_the_bits_of_full<HybridLeapfrog, qp, MapperChoice{false, true, true, false},
                                   true>("basin = { period = 5.0 }\n", "hybrid_leapfrog");
  expect_lean_has_the_bits_of_full<HybridLeapfrog, qp, MapperChoice{true, true, false, true},
                                   true>("basin = { recurrence = true }\n", "hybrid_leapfrog");
  // An adaptive method carries z and ln λ always (RunPlan).
  expect_lean_has_the_bits_of_full<Dop853, Carry{true, true, false},
                                   MapperChoice{true, true, false, false}, false>("basin = {}\n",
                                                                                 "dop853");
}

}  // namespace
}  // namespace cs
