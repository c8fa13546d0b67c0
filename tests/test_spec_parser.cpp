// The spec parser: defaults, grid order, --set, the stored spec text. Elsewhere: numpy-exact
// linspace (test_linspace.cpp) and the refusals, a corpus of bad inputs whose messages must name
// what is wrong (test_spec_refusals.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"
#include "support/private_temp_dir.hpp"
#include "support/spec_parsing.hpp"

namespace cs {
namespace {

using namespace test;  // parse, message_of, expect_input_error, kDoubleWell, kCoupled, kSweep

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

std::vector<std::string> axis_names(const RunSpec& spec) {
  std::vector<std::string> names;
  for (const GridAxis& axis : spec.axes) names.push_back(axis.name);
  return names;
}

// Field by field, doubles bit for bit: what "re-parses to the same RunSpec" means.
void expect_same(const RunSpec& a, const RunSpec& b) {
  EXPECT_EQ(a.title, b.title);
  EXPECT_EQ(a.scene, b.scene);
  EXPECT_EQ(a.parameters, b.parameters);
  EXPECT_EQ(a.initial, b.initial);
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(bits(a.h), bits(b.h));
  EXPECT_EQ(bits(a.t_end), bits(b.t_end));
  EXPECT_EQ(a.steps, b.steps);
  ASSERT_EQ(a.axes.size(), b.axes.size());
  for (std::size_t i = 0; i < a.axes.size(); ++i) {
    EXPECT_EQ(a.axes[i].name, b.axes[i].name);
    EXPECT_EQ(a.axes[i].target, b.axes[i].target);
    EXPECT_EQ(a.axes[i].is_parameter, b.axes[i].is_parameter);
    EXPECT_EQ(a.axes[i].values, b.axes[i].values);
  }
  const Measures& ma = a.measures;
  const Measures& mb = b.measures;
  ASSERT_EQ(ma.final_state.has_value(), mb.final_state.has_value());
  if (ma.final_state) {
    EXPECT_EQ(ma.final_state->vars, mb.final_state->vars);
  }
  ASSERT_EQ(ma.trajectory.has_value(), mb.trajectory.has_value());
  if (ma.trajectory) {
    EXPECT_EQ(ma.trajectory->every, mb.trajectory->every);
  }
  ASSERT_EQ(ma.basin.has_value(), mb.basin.has_value());
  if (ma.basin) {
    EXPECT_EQ(ma.basin->early_stop, mb.basin->early_stop);
  }
  ASSERT_EQ(ma.sync.has_value(), mb.sync.has_value());
  if (ma.sync) {
    EXPECT_EQ(bits(ma.sync->window_from), bits(mb.sync->window_from));
    EXPECT_EQ(bits(ma.sync->window_to), bits(mb.sync->window_to));
  }
  EXPECT_EQ(a.spec_text, b.spec_text);
}

// ---------------------------------------------------------------------------------------------
// Defaults

TEST(SpecParser, MinimalSpecTakesEveryDefaultFromTheCatalog) {
  for (const SceneInfo& scene : scene_catalog()) {
    SCOPED_TRACE(scene.name);
    const RunSpec spec = parse("[scene]\nname = \"" + scene.name + "\"\n");
    EXPECT_EQ(spec.scene, scene.name);
    ASSERT_EQ(spec.parameters.size(), scene.parameters.size());
    for (const ParameterInfo& p : scene.parameters)
      EXPECT_EQ(spec.parameters.at(p.name), p.paper_value);
    ASSERT_EQ(spec.initial.size(), scene.variables.size());
    for (const VariableInfo& v : scene.variables) EXPECT_EQ(spec.initial.at(v.name), v.paper_value);
    EXPECT_EQ(spec.method, "hybrid_leapfrog");
    EXPECT_EQ(spec.h, scene.default_h);
    EXPECT_EQ(spec.t_end, scene.default_t_end);
    EXPECT_EQ(spec.steps, std::llround(scene.default_t_end / scene.default_h));
    EXPECT_EQ(spec.title, scene.name + " with hybrid_leapfrog");
    EXPECT_TRUE(spec.axes.empty());
    EXPECT_EQ(spec.grid_points(), 1);
    // No [measures]: the final state of every variable, nothing else.
    ASSERT_TRUE(spec.measures.final_state.has_value());
    std::vector<std::string> all;
    for (const VariableInfo& v : scene.variables) all.push_back(v.name);
    EXPECT_EQ(spec.measures.final_state->vars, all);
    EXPECT_FALSE(spec.measures.trajectory || spec.measures.basin || spec.measures.sync);
  }
}

TEST(SpecParser, GivenValuesReplaceDefaults) {
  const RunSpec spec = parse(R"(title = "mine"
[scene]
name = "double_well"
gamma = 0.25
a = 2
[initial]
q = -1.5
lambda = 3
[integrator]
h = 0.02
t_end = 50
)");
  EXPECT_EQ(spec.title, "mine");
  EXPECT_EQ(spec.parameters.at("gamma"), 0.25);
  EXPECT_EQ(spec.parameters.at("a"), 2.0);  // an integer is a number too
  EXPECT_EQ(spec.initial.at("q"), -1.5);
  EXPECT_EQ(spec.initial.at("p"), 0.0);
  EXPECT_EQ(spec.initial.at("lambda"), 3.0);
  EXPECT_EQ(spec.h, 0.02);
  EXPECT_EQ(spec.t_end, 50.0);
  EXPECT_EQ(spec.steps, 2500);
}

TEST(SpecParser, StepCountRoundsWhenTEndIsAWholeNumberOfSteps) {
  // 0.3 / 0.01 = 29.999999999999996 in doubles: still 30 steps.
  EXPECT_EQ(parse(kDoubleWell + "[integrator]\nh = 0.01\nt_end = 0.3\n").steps, 30);
  EXPECT_EQ(parse(kDoubleWell + "[integrator]\nh = 0.1\nt_end = 100\n").steps, 1000);
  EXPECT_EQ(parse(kDoubleWell + "[integrator]\nh = 0.01\nt_end = 0.01\n").steps, 1);
  EXPECT_EQ(parse(kDoubleWell + "[integrator]\nh = 0.001\nt_end = 1e4\n").steps, 10'000'000);
}

// ---------------------------------------------------------------------------------------------
// Grid

TEST(SpecParser, GridAxesKeepFileOrderWhateverTheirForm) {
  // Key order would be a, gamma, p_0, q_0, z_0; the file says otherwise.
  const RunSpec spec = parse(kDoubleWell + R"(
[grid]
q_0 = { from = -3.0, to = 3.0, n = 4 }
gamma = { values = [0.1, 0.2] }
z_0.from = 0.5
z_0.to = 1.5
z_0.n = 3

[grid.p_0]
values = [0.0]

[grid.a]
from = 1
to = 2
n = 2
)");
  EXPECT_EQ(axis_names(spec), (std::vector<std::string>{"q_0", "gamma", "z_0", "p_0", "a"}));
  EXPECT_EQ(spec.grid_points(), 4 * 2 * 3 * 1 * 2);
  EXPECT_EQ(spec.axes[0].target, "q");
  EXPECT_FALSE(spec.axes[0].is_parameter);
  EXPECT_EQ(spec.axes[1].target, "gamma");
  EXPECT_TRUE(spec.axes[1].is_parameter);
  EXPECT_EQ(spec.axes[1].values, (std::vector<double>{0.1, 0.2}));
  EXPECT_EQ(spec.axes[2].values, linspace(0.5, 1.5, 3));
}

TEST(SpecParser, EveryVariableAndParameterCanBeAnAxis) {
  const RunSpec spec = parse(kCoupled + R"(
[grid]
p1_0 = { values = [0.0, 1.0] }
g = { values = [0.0, 0.8] }
lambda_0 = { values = [1.0, 2.0] }
z_0 = { values = [1.0] }
)");
  ASSERT_EQ(spec.axes.size(), 4u);
  EXPECT_EQ(spec.axes[0].target, "p1");
  EXPECT_EQ(spec.axes[1].target, "g");
  EXPECT_TRUE(spec.axes[1].is_parameter);
  EXPECT_EQ(spec.axes[2].target, "lambda");
  EXPECT_EQ(spec.axes[3].target, "z");
}

TEST(SpecParser, GridAxisWinsOverTheSceneValue) {
  // The [scene] value stays as the base value; the axis replaces it point by point.
  const RunSpec spec = parse(kDoubleWell +
                             "gamma = 0.3\n[initial]\nq = 1.0\n[grid]\n"
                             "gamma = { values = [0.1, 0.2] }\nq_0 = { values = [5.0] }\n");
  EXPECT_EQ(spec.parameters.at("gamma"), 0.3);
  EXPECT_EQ(spec.initial.at("q"), 1.0);
  EXPECT_EQ(spec.axes[0].values, (std::vector<double>{0.1, 0.2}));
  EXPECT_EQ(spec.axes[1].values, (std::vector<double>{5.0}));
}


// A parameter of K that a grid axis sweeps needs no value under [scene]: the axis gives every
// lane its value, and the run's base value is the axis's first. A value given there anyway is
// still accepted (specs written before keep their meaning and their outputs' bits).
TEST(SpecParser, SweptParameterOfKNeedsNoValueUnderScene) {
  const std::string k = "[scene]\nK = \"p^2/2 + q^2/2 - gamma*z\"\n";
  const RunSpec swept = parse(k + "[grid]\ngamma = { values = [0.2, 0.1] }\n");
  ASSERT_EQ(swept.axes.size(), 1U);
  EXPECT_TRUE(swept.axes[0].is_parameter);
  EXPECT_EQ(swept.axes[0].target, "gamma");
  EXPECT_EQ(swept.axes[0].values, (std::vector<double>{0.2, 0.1}));
  EXPECT_EQ(swept.parameters.at("gamma"), 0.2);

  const RunSpec by_set = parse(k, {"grid.gamma.values=[0.2, 0.1]"});
  EXPECT_EQ(by_set.axes[0].values, swept.axes[0].values);
  EXPECT_EQ(by_set.parameters, swept.parameters);

  const RunSpec dummy = parse(k + "gamma = 7.0\n[grid]\ngamma = { values = [0.2, 0.1] }\n");
  EXPECT_EQ(dummy.axes[0].values, swept.axes[0].values);
  EXPECT_EQ(dummy.parameters.at("gamma"), 7.0);
  // The spec text without the dummy reparses to the same run.
  expect_same(swept, parse(swept.spec_text));
}

TEST(SpecParser, GridBeyondTheMemoryBudgetIsRefusedBeforeAnyCoordinateIsBuilt) {
  // 2^40 points pass the index check but need 1 TiB: refused before linspace fills 2 x 8 MiB.
  const std::string huge = kDoubleWell +
                           "[grid]\nq_0 = { from = 0, to = 1, n = 1048576 }\n"
                           "p_0 = { from = 0, to = 1, n = 1048576 }\n";
  expect_input_error(huge, "the grid has 1099511627776 points and needs at least 1.02e+03 GiB");
}

// Sets CONTACTSWEEP_MEMORY_LIMIT for one test and restores the environment after it.
class MemoryLimit {
 public:
  explicit MemoryLimit(const char* value) { setenv(kName, value, 1); }
  ~MemoryLimit() { unsetenv(kName); }

 private:
  static constexpr const char* kName = "CONTACTSWEEP_MEMORY_LIMIT";
};

TEST(SpecParser, MemoryLimitFromTheEnvironmentBoundsTheGrid) {
  const MemoryLimit limit("1M");  // 0.8 MiB usable: 838860 bytes
  // One byte a point (a basin map's compact label) and the coordinates as doubles:
  // 900 x 900 = 810000 + 1800 x 8 = 824400 bytes: fits.
  EXPECT_EQ(parse(kDoubleWell + "[grid]\nq_0 = { from = 0, to = 1, n = 900 }\n"
                                "p_0 = { from = 0, to = 1, n = 900 }\n")
                .grid_points(),
            810000);
  // 912 x 912 = 831744 + 1824 x 8 = 846336 bytes: over.
  expect_input_error(kDoubleWell + "[grid]\nq_0 = { from = 0, to = 1, n = 912 }\n"
                                   "p_0 = { from = 0, to = 1, n = 912 }\n",
                     "the grid has 831744 points");
}

TEST(SpecParser, MalformedMemoryLimitIsNamed) {
  for (const char* bad : {"12X", "", "-5", "0", "8GB", "1.5G"}) {
    const MemoryLimit limit(bad);
    expect_input_error(kDoubleWell + "[grid]\nq_0 = { values = [1] }\n",
                       "CONTACTSWEEP_MEMORY_LIMIT='" + std::string(bad) + "': expected a whole "
                       "number of bytes > 0");
  }
}

// ---------------------------------------------------------------------------------------------
// Measures

TEST(SpecParser, MeasureForms) {
  const RunSpec spec = parse(kDoubleWell + R"(
[measures]
final_state = { vars = ["lambda", "q"] }
trajectory = true
basin = { early_stop = false }
)");
  // Stored in the scene's variable order, not the order listed.
  EXPECT_EQ(spec.measures.final_state->vars, (std::vector<std::string>{"q", "lambda"}));
  EXPECT_EQ(spec.measures.trajectory->every, 1);
  EXPECT_FALSE(spec.measures.basin->early_stop);
  EXPECT_FALSE(spec.measures.sync.has_value());

  const RunSpec other = parse(kDoubleWell +
                              "[measures]\nfinal_state = false\ntrajectory = { every = 10 }\n"
                              "basin = {}\n");
  EXPECT_FALSE(other.measures.final_state.has_value());
  EXPECT_EQ(other.measures.trajectory->every, 10);
  EXPECT_TRUE(other.measures.basin->early_stop);
}

TEST(SpecParser, RecurrenceMapperSettingsAndTheirDefaults) {
  const RunSpec given = parse(kDoubleWell + R"(
[measures]
basin = { recurrence = true, cell_size = 0.05, recurrences = 30, locate = 200, max_cells = 999, box = { p = [-3, 2.5] } }
)");
  const RecurrenceSettings& r = given.measures.basin->recurrence;
  EXPECT_EQ(r.enabled, std::optional<bool>(true));
  EXPECT_EQ(r.cell_size, std::optional<double>(0.05));
  EXPECT_EQ(r.recurrences, 30);
  EXPECT_EQ(r.locate, 200);
  EXPECT_EQ(r.max_cells, 999);
  EXPECT_EQ(r.box.at("p"), (std::array<double, 2>{-3.0, 2.5}));
  // Attractors.jl's defaults; on or off, and the cells' size, decided by the run plan.
  const RecurrenceSettings d = parse(kDoubleWell + "[measures]\nbasin = {}\n").measures.basin->recurrence;
  EXPECT_FALSE(d.enabled.has_value());
  EXPECT_FALSE(d.cell_size.has_value());
  EXPECT_EQ(d.recurrences, 100);
  EXPECT_EQ(d.locate, 1000);
  EXPECT_TRUE(d.box.empty());
}

// The stroboscopic map of a fixed-step method needs a whole number of steps per period; an
// adaptive method samples it at t_start + k·period from its steps' dense output, whatever h
// (its first step) is: counted samples, the last at or a rounding's hair below t_end.
TEST(SpecParser, AnAdaptiveMethodsStroboscopicPeriodNeedNotDivideIntoSteps) {
  const std::string strobe = kDoubleWell +
                             "[integrator]\nh = 0.1\nt_end = 100.0\n{}[measures]\n"
                             "basin = { period = 3.141592653589793 }\n";
  auto with = [&](const std::string& method) {
    std::string text = strobe;
    return text.replace(text.find("{}"), 2, method);
  };
  expect_input_error(with("method = \"rk4\"\n"),
                     "measures.basin.period = 3.141592653589793: the stroboscopic map needs a whole "
                     "number of steps per period");
  const RunSpec spec = parse(with("method = \"dop853\"\nrtol = 1e-8\n"));
  const RunPlan plan(spec, *find_scene(spec.scene), *find_method(spec.method));
  EXPECT_TRUE(plan.attractors.dense_strobe);
  EXPECT_EQ(plan.attractors.sample_steps, 1);
  EXPECT_EQ(plan.attractors.strobe_last, 31);  // 31 pi = 97.4 <= 100 < 32 pi
  EXPECT_EQ(plan.attractors.dwell_samples, 16);  // the default dwell: 16 periods
  EXPECT_EQ(plan.chunk, 32);  // not cut to divide a period: its samples fall inside steps
}

TEST(SpecParser, SyncWindowGivenOrSecondHalfOfTheRun) {
  const RunSpec given = parse(kCoupled + "[measures]\nsync = { window = [50.0, 100] }\n");
  EXPECT_EQ(given.measures.sync->window_from, 50.0);
  EXPECT_EQ(given.measures.sync->window_to, 100.0);
  const RunSpec by_default =
      parse(kCoupled + "[integrator]\nt_end = 80\n[measures]\nsync = true\n");
  EXPECT_EQ(by_default.measures.sync->window_from, 40.0);
  EXPECT_EQ(by_default.measures.sync->window_to, 80.0);
}

TEST(SpecParser, EachSceneAcceptsExactlyTheMeasuresItSupports) {
  for (const SceneInfo& scene : scene_catalog()) {
    for (const char* measure : {"final_state", "trajectory", "basin", "sync", "lyapunov"}) {
      SCOPED_TRACE(scene.name + " / " + measure);
      const std::string text =
          "[scene]\nname = \"" + scene.name + "\"\n[measures]\n" + measure + " = true\n";
      const bool supported =
          std::find(scene.measures.begin(), scene.measures.end(), measure) != scene.measures.end();
      if (supported) {
        EXPECT_NO_THROW(parse(text));
      } else {
        EXPECT_NE(message_of(text).find("scene '" + scene.name + "' does not support"),
                  std::string::npos);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// --set

TEST(SpecParser, SetOverridesValuesByDottedKey) {
  const RunSpec spec = parse(kSweep, {"integrator.h=0.005", "scene.gamma=0.2", "initial.q=1.5",
                                      "title = \"overridden\"", "scene.a=2"});
  EXPECT_EQ(spec.h, 0.005);
  EXPECT_EQ(spec.steps, 20000);
  EXPECT_EQ(spec.parameters.at("gamma"), 0.2);
  EXPECT_EQ(spec.parameters.at("a"), 2.0);
  EXPECT_EQ(spec.initial.at("q"), 1.5);
  EXPECT_EQ(spec.title, "overridden");
}

TEST(SpecParser, SetGridSizeKeepsTheAxisInPlace) {
  const RunSpec spec = parse(kSweep, {"grid.q_0.n=64"});
  EXPECT_EQ(axis_names(spec), (std::vector<std::string>{"p_0", "q_0", "gamma"}));
  EXPECT_EQ(spec.axes[1].values, linspace(-3.0, 3.0, 64));
  EXPECT_NE(spec.spec_text.find("q_0 = { from = -3.0, to = 3.0, n = 64 }"), std::string::npos);
}

TEST(SpecParser, SetReplacingAnAxisKeepsItsPlaceAndNewAxesComeLast) {
  const RunSpec spec =
      parse(kSweep, {"grid.q_0={ values = [1.0, 2.0] }", "grid.a={ from = 0, to = 1, n = 8 }",
                     "grid.z_0.values=[1.0]"});
  EXPECT_EQ(axis_names(spec), (std::vector<std::string>{"p_0", "q_0", "gamma", "a", "z_0"}));
  EXPECT_EQ(spec.axes[1].values, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(spec.axes[3].values, linspace(0.0, 1.0, 8));
}

TEST(SpecParser, SetCreatesMissingSectionsAndKeys) {
  const RunSpec spec = parse(kDoubleWell, {"measures.basin.early_stop=false",
                                           "grid={ q_0 = { values = [1.0] }, "
                                           "gamma = { values = [0.1, 0.2] } }"});
  ASSERT_TRUE(spec.measures.basin.has_value());
  EXPECT_FALSE(spec.measures.basin->early_stop);
  EXPECT_FALSE(
      spec.measures.final_state.has_value());  // [measures] now exists and asks for basin only
  EXPECT_EQ(axis_names(spec), (std::vector<std::string>{"q_0", "gamma"}));  // as written in VALUE
}

TEST(SpecParser, SetTakesABareWordAsAString) {
  // The shell turns --set scene.name="z2_damping" into scene.name=z2_damping.
  const RunSpec spec =
      parse(kDoubleWell, {"scene.name=z2_damping", "integrator.method='hybrid_leapfrog'"});
  EXPECT_EQ(spec.scene, "z2_damping");
}

TEST(SpecParser, SetAppliesInOrder) {
  EXPECT_EQ(parse(kDoubleWell, {"integrator.h=0.1", "integrator.h=0.02"}).h, 0.02);
}

// ---------------------------------------------------------------------------------------------
// spec_text

TEST(SpecParser, SpecTextReparsesToTheSameRunSpec) {
  const std::string text = R"(title = "A \"quoted\" title\twith tab, ümlaut and a\nnewline"
[measures]
trajectory = { every = 7 }
basin = {}
final_state = { vars = ["p"] }
[grid]
gamma = { from = 0.1, to = 0.30000000000000004, n = 5 }
q_0 = { values = [1e-300, -0.0, 2.5e+10, 3] }
[integrator]
t_end = 10
[scene]
gamma = 0.1
name = "double_well"
)";
  const RunSpec spec = parse(text, {"grid.gamma.n=6", "initial.lambda=0.7"});
  const RunSpec again = parse(spec.spec_text);
  expect_same(spec, again);
  EXPECT_EQ(axis_names(again), (std::vector<std::string>{"gamma", "q_0"}));
  EXPECT_EQ(again.title, "A \"quoted\" title\twith tab, ümlaut and a\nnewline");
  EXPECT_EQ(again.axes[1].values[1], 0.0);
  EXPECT_TRUE(std::signbit(again.axes[1].values[1]));  // -0.0 survives
}

TEST(SpecParser, SpecTextIsTheSpecAfterSetInAFixedLayout) {
  const RunSpec spec = parse(kSweep, {"grid.q_0.n=64", "measures.basin={}"});
  EXPECT_EQ(spec.spec_text, R"([scene]
name = "double_well"

[integrator]
h = 0.01
t_end = 100.0

[grid]
p_0 = { values = [0.0, 0.5] }
q_0 = { from = -3.0, to = 3.0, n = 64 }
gamma = { values = [0.1] }

[measures]
basin = {}
)");
}

// ---------------------------------------------------------------------------------------------
// Files, methods

TEST(SpecParser, LoadReadsTheFileAndNamesItInMessages) {
  const cs::test::PrivateTempDir temp("contactsweep_spec_parser_");
  const std::filesystem::path& dir = temp.path();
  const std::string path = temp.file("spec.toml");
  std::ofstream(path) << kDoubleWell << "[integrator]\nh = 0.02\n";
  EXPECT_EQ(load_run_spec(path, {}).h, 0.02);
  std::ofstream(path) << kDoubleWell << "[integrator]\nh = -1\n";
  try {
    load_run_spec(path, {});
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path + ":4:5: integrator.h = -1"), std::string::npos)
        << error.what();
  }
  const std::string missing = (dir / "no_such_spec.toml").string();
  EXPECT_THROW(
      {
        try {
          load_run_spec(missing, {});
        } catch (const InputError& error) {
          EXPECT_NE(std::string(error.what()).find(missing), std::string::npos);
          throw;
        }
      },
      InputError);
  EXPECT_THROW(load_run_spec(dir.string(), {}), InputError);
}

// Every scene of the catalog offers the sub-flows every method composes (scene B's -gamma z^2
// part has an exact flow too), so the refusal is checked on a scene that offers fewer.
TEST(SpecParser, EverySceneOffersTheSubFlowsOfEveryMethod) {
  for (const SceneInfo& scene : scene_catalog())
    for (const MethodInfo& method : method_catalog())
      EXPECT_TRUE(missing_split_parts(method, scene.split_parts).empty())
          << method.name << " on " << scene.name;
}

TEST(SpecParser, SplittingOnASceneWithoutThatSubFlowIsRefused) {
  const std::vector<std::string> no_potential_flow{"kinetic", "z_linear"};
  int refused = 0;
  for (const MethodInfo& method : method_catalog()) {
    const auto missing = missing_split_parts(method, no_potential_flow);
    const bool splits = method.name.starts_with("contact_splitting");
    EXPECT_EQ(missing, splits ? std::vector<std::string>{"potential"} : std::vector<std::string>{})
        << method.name;
    refused += !missing.empty();
  }
  EXPECT_EQ(refused, 3);  // contact_splitting2, 4 and 6; the leap-frogs and rk4 need no sub-flow
}

}  // namespace
}  // namespace cs
