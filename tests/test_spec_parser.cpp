// The spec parser: defaults, grid order, numpy-exact linspace, --set, the stored spec text, and a
// corpus of bad inputs whose messages must name what is wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

RunSpec parse(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return parse_run_spec(text, overrides, "test.toml");
}

std::string message_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse(text, overrides);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no InputError)";
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

const std::string kDoubleWell = "[scene]\nname = \"double_well\"\n";
const std::string kCoupled = "[scene]\nname = \"coupled_oscillators\"\n";

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

void expect_input_error(const std::string& text, const std::string& fragment) {
  const std::string message = message_of(text);
  EXPECT_NE(message.find(fragment), std::string::npos) << message;
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
  // 2^40 points pass the index check but need 8 TiB: refused before linspace fills 2 x 8 MiB.
  const std::string huge = kDoubleWell +
                           "[grid]\nq_0 = { from = 0, to = 1, n = 1048576 }\n"
                           "p_0 = { from = 0, to = 1, n = 1048576 }\n";
  expect_input_error(huge, "the grid has 1099511627776 points and needs at least 8.19e+03 GiB");
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
  const MemoryLimit limit("1M");  // 0.8 MiB usable: 104857 doubles
  // 320 x 320 = 102400 points + 640 coordinates = 103040 doubles: fits.
  EXPECT_EQ(parse(kDoubleWell + "[grid]\nq_0 = { from = 0, to = 1, n = 320 }\n"
                                "p_0 = { from = 0, to = 1, n = 320 }\n")
                .grid_points(),
            102400);
  // 324 x 324 = 104976 + 648 doubles: over.
  expect_input_error(kDoubleWell + "[grid]\nq_0 = { from = 0, to = 1, n = 324 }\n"
                                   "p_0 = { from = 0, to = 1, n = 324 }\n",
                     "the grid has 104976 points");
}

TEST(SpecParser, MalformedMemoryLimitIsNamed) {
  for (const char* bad : {"12X", "", "-5", "0", "8GB", "1.5G"}) {
    const MemoryLimit limit(bad);
    expect_input_error(kDoubleWell + "[grid]\nq_0 = { values = [1] }\n",
                       "CONTACTSWEEP_MEMORY_LIMIT='" + std::string(bad) + "': expected a whole "
                       "number of bytes > 0");
  }
}

// numpy.linspace, bit for bit. The expected values were produced with numpy 1.24.2:
//   /usr/bin/python3 -c "import numpy as np; y = np.linspace(FROM, TO, N);
//                        print([(i, float(y[i]).hex()) for i in INDICES])"
// Where noted, they differ from the naive from + i * (to - from) / (n - 1).
struct LinspaceCase {
  double from, to;
  std::int64_t n;
  std::vector<std::pair<std::int64_t, double>> expected;  // (index, numpy's value)
};

const std::vector<LinspaceCase> kLinspaceCases = {
    // np.linspace(-3.0, 3.0, 512): differs from the naive formula at 139 indices.
    {-0x1.8p+1,
     0x1.8p+1,
     512,
     {{0, -0x1.8000000000000p+1},
      {1, -0x1.7e7f3f9fcfe7fp+1},
      {2, -0x1.7cfe7f3f9fcfep+1},
      {100, -0x1.d369b4da6d36ap+0},
      {255, -0x1.80c0603018200p-8},
      {256, 0x1.80c0603018000p-8},
      {257, 0x1.2090482412080p-6},
      {383, 0x1.7f3f9fcfe7f40p+0},
      {510, 0x1.7e7f3f9fcfe7ep+1},
      {511, 0x1.8000000000000p+1}}},
    // np.linspace(0.0, 1.0, 7)
    {0.0,
     1.0,
     7,
     {{0, 0x0.0p+0},
      {1, 0x1.5555555555555p-3},
      {2, 0x1.5555555555555p-2},
      {3, 0x1.0p-1},
      {4, 0x1.5555555555555p-1},
      {5, 0x1.aaaaaaaaaaaaap-1},
      {6, 0x1.0p+0}}},
    // np.linspace(0.1, 0.7, 13)
    {0x1.999999999999ap-4,
     0x1.6666666666666p-1,
     13,
     {{0, 0x1.999999999999ap-4},
      {1, 0x1.3333333333333p-3},
      {2, 0x1.999999999999ap-3},
      {3, 0x1.0p-2},
      {4, 0x1.3333333333333p-2},
      {5, 0x1.6666666666666p-2},
      {6, 0x1.999999999999ap-2},
      {7, 0x1.cccccccccccccp-2},
      {8, 0x1.0p-1},
      {9, 0x1.1999999999999p-1},
      {10, 0x1.3333333333333p-1},
      {11, 0x1.4ccccccccccccp-1},
      {12, 0x1.6666666666666p-1}}},
    // np.linspace(0.0, 5e-324, 4): the step underflows to 0, numpy's i / div * delta branch.
    {0.0,
     0x0.0000000000001p-1022,
     4,
     {{0, 0.0}, {1, 0.0}, {2, 0x0.0000000000001p-1022}, {3, 0x0.0000000000001p-1022}}},
    // np.linspace(1.0, 0.0, 3): descending.
    {1.0, 0.0, 3, {{0, 0x1.0p+0}, {1, 0x1.0p-1}, {2, 0.0}}},
    // np.linspace(5.0, -5.0, 1): a single point is `from`.
    {5.0, -5.0, 1, {{0, 0x1.4p+2}}},
    // np.linspace(-2.5, 7.3, 1000): differs from the naive formula at 238 indices.
    {-2.5,
     0x1.d333333333333p+2,
     1000,
     {{0, -0x1.4p+1},
      {1, -0x1.3ebe8d59d7ebfp+1},
      {3, -0x1.3c3ba80d87c3cp+1},
      {333, 0x1.888888888888cp-1},
      {499, 0x1.329279e01f294p+1},
      {500, 0x1.33d3ec86473d4p+1},
      {666, 0x1.0222222222223p+2},
      {997, 0x1.d1f1c08d0b1f2p+2},
      {998, 0x1.d29279e01f294p+2},
      {999, 0x1.d333333333333p+2}}},
    // np.linspace(0.001, 1000.0, 9)
    {0x1.0624dd2f1a9fcp-10,
     1000.0,
     9,
     {{0, 0x1.0624dd2f1a9fcp-10},
      {1, 0x1.f400e56041894p+6},
      {2, 0x1.f400624dd2f1bp+7},
      {3, 0x1.770028f5c28f6p+8},
      {4, 0x1.f40020c49ba5ep+8},
      {5, 0x1.38800c49ba5e3p+9},
      {6, 0x1.7700083126e98p+9},
      {7, 0x1.b58004189374cp+9},
      {8, 0x1.f4p+9}}},
};

TEST(Linspace, MatchesNumpyBitForBit) {
  for (const LinspaceCase& c : kLinspaceCases) {
    const std::vector<double> y = linspace(c.from, c.to, c.n);
    ASSERT_EQ(std::ssize(y), c.n);
    for (const auto& [i, expected] : c.expected)
      EXPECT_EQ(bits(y[i]), bits(expected))
          << "linspace(" << c.from << ", " << c.to << ", " << c.n << ")[" << i << "] = " << y[i]
          << ", numpy: " << expected;
  }
}

TEST(Linspace, GridAxisUsesIt) {
  const RunSpec spec = parse(kDoubleWell + "[grid]\nq_0 = { from = -3, to = 3.0, n = 512 }\n");
  EXPECT_EQ(spec.axes[0].values, linspace(-3.0, 3.0, 512));
  EXPECT_EQ(bits(spec.axes[0].values[255]), bits(-0x1.80c0603018200p-8));
}

TEST(Linspace, NoPointsForNonPositiveCounts) {
  EXPECT_TRUE(linspace(0.0, 1.0, 0).empty());
  EXPECT_TRUE(linspace(0.0, 1.0, -3).empty());
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

const std::string kSweep = kDoubleWell + R"(
[integrator]
h = 0.01
t_end = 100.0

[grid]
p_0 = { values = [0.0, 0.5] }
q_0 = { from = -3.0, to = 3.0, n = 512 }
gamma = { values = [0.1] }
)";

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
  const auto dir = std::filesystem::temp_directory_path() / "contactsweep_spec_parser_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "spec.toml").string();
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
  std::filesystem::remove_all(dir);
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

// ---------------------------------------------------------------------------------------------
// Bad inputs: each must throw InputError whose message contains the fragment, and every message
// starts with where the problem is (the file position or the --set argument).

struct BadSpec {
  const char* name;
  std::string text;
  std::vector<std::string> overrides;
  std::string fragment;
};

std::ostream& operator<<(std::ostream& out, const BadSpec& bad) { return out << bad.name; }

const std::string kDw = kDoubleWell;  // short name for the table below

// clang-format off
const std::vector<BadSpec> kBadSpecs = {
    // Malformed TOML: position of the problem.
    {"unclosed_array", kDw + "[grid]\nq_0 = { values = [1, 2 }\n", {}, "test.toml:4:"},
    {"duplicate_key", kDw + "name = \"z2_damping\"\n", {}, "test.toml:3:8: malformed TOML"},
    {"duplicate_axis", kDw + "[grid]\nq_0 = { values = [1] }\nq_0 = { values = [2] }\n", {},
     "cannot redefine existing table 'q_0'"},
    {"duplicate_axis_header", kDw + "[grid]\nq_0 = { values = [1] }\n[grid.q_0]\nn = 3\n", {},
     "cannot redefine existing table 'grid.q_0'"},
    {"bare_string", "[scene]\nname = double_well\n", {}, "test.toml:2:"},
    // Unknown sections and keys, with the closest valid key.
    {"unknown_section", kDw + "[integrater]\nh = 0.1\n", {},
     "unknown key 'integrater' (did you mean 'integrator'?)"},
    {"alias_stepsize", kDw + "[integrator]\nstepsize = 0.1\n", {},
     "unknown key 'integrator.stepsize' (did you mean 'integrator.h'?)"},
    {"alias_tmax", kDw + "[integrator]\ntmax = 10\n", {}, "did you mean 'integrator.t_end'?"},
    {"typo_parameter", kDw + "gama = 0.1\n", {},
     "unknown key 'scene.gama' (did you mean 'scene.gamma'?)"},
    {"transposed_key", kDw + "[integrator]\nt_ned = 10\n", {}, "did you mean 'integrator.t_end'?"},
    {"key_of_other_section", kDw + "[integrator]\ngamma = 0.1\n", {},
     "did you mean 'scene.gamma'?"},
    {"key_lands_in_scene", kDw + "h = 0.1\n", {},
     "unknown key 'scene.h' (did you mean 'integrator.h'?)"},
    {"top_level_key", "h = 0.1\n" + kDw, {}, "unknown key 'h' (did you mean 'integrator.h'?)"},
    {"initial_with_suffix", kDw + "[initial]\nq_0 = 1.0\n", {},
     "unknown key 'initial.q_0' (did you mean 'initial.q'?)"},
    {"parameter_of_other_scene", kDw + "omega = 1.0\n", {},
     "valid keys in [scene]: name, a, gamma"},
    {"axis_without_suffix", kDw + "[grid]\nq = { values = [1] }\n", {},
     "unknown key 'grid.q' (did you mean 'grid.q_0'?)"},
    {"axis_unknown", kDw + "[grid]\nomega = { values = [1] }\n", {},
     "valid keys in [grid]: a, gamma, h, q_0, p_0, z_0, lambda_0"},
    {"axis_unknown_key", kDw + "[grid]\nq_0 = { start = 0, to = 1, n = 2 }\n", {},
     "unknown key 'grid.q_0.start' (did you mean 'grid.q_0.from'?)"},
    {"measure_unknown", kDw + "[measures]\nbasins = {}\n", {},
     "unknown key 'measures.basins' (did you mean 'measures.basin'?)"},
    {"measure_unknown_key", kDw + "[measures]\ntrajectory = { stride = 2 }\n", {},
     "did you mean 'measures.trajectory.every'?"},
    // Scenes and methods.
    {"missing_scene", "[integrator]\nh = 0.1\n", {},
     "missing [scene] section with name = one of: damped_oscillator, z2_damping, double_well, "
     "coupled_oscillators"},
    {"missing_scene_name", "[scene]\ngamma = 0.1\n", {},
     "scene.name is missing; valid scenes: damped_oscillator"},
    {"unknown_scene", "[scene]\nname = \"duble_well\"\n", {},
     "unknown scene \"duble_well\" (did you mean 'double_well'?); valid scenes: damped_oscillator, "
     "z2_damping, double_well, coupled_oscillators"},
    {"step_axis_not_first", kDw + "[grid]\nq_0 = { values = [1.0] }\nh = { values = [0.01] }\n", {},
     "grid.h must be the first grid axis"},
    {"step_axis_not_whole", kDw + "[integrator]\nt_end = 1.0\n[grid]\nh = { values = [0.3] }\n", {},
     "grid.h = 0.3: t_end = 1 is not a whole number of steps"},
    {"step_axis_with_trajectory", kDw + "[grid]\nh = { values = [0.01] }\n[measures]\ntrajectory = true\n", {},
     "measures.trajectory cannot be combined with a grid over h"},
    {"unknown_method", kDw + "[integrator]\nmethod = \"rk5\"\n", {},
     "unknown method \"rk5\" (did you mean 'rk4'?); valid methods: hybrid_leapfrog, "
     "symmetric_leapfrog, contact_splitting2, contact_splitting4, contact_splitting6, rk4, "
     "dop853"},
    // An adaptive method's tolerances, and what it does not support yet.
    {"dop853_without_rtol", kDw + "[integrator]\nmethod = \"dop853\"\n", {},
     "method \"dop853\" is adaptive: integrator.rtol (its relative tolerance, e.g. 1e-8) is "
     "required"},
    {"dop853_rtol_zero", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = 0.0\n", {},
     "integrator.rtol = 0.0: expected a finite number > 0"},
    {"dop853_rtol_negative", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = -1e-8\n", {},
     "integrator.rtol = -1e-08: expected a finite number > 0"},
    {"dop853_atol_zero", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = 1e-8\natol = 0.0\n", {},
     "integrator.atol = 0.0: expected a finite number > 0"},
    {"rtol_for_fixed_step", kDw + "[integrator]\nmethod = \"rk4\"\nrtol = 1e-8\n", {},
     "integrator.rtol is a tolerance of an adaptive method (dop853); method \"rk4\" steps at "
     "the fixed h"},
    {"atol_for_default_method", kDw + "[integrator]\natol = 1e-8\n", {},
     "integrator.atol is a tolerance of an adaptive method"},
    {"dop853_trajectory", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = 1e-8\n[measures]\ntrajectory = true\n", {},
     "method \"dop853\" does not support measures.trajectory yet"},
    {"dop853_basin_period", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = 1e-8\n[measures]\nbasin = { period = 1.0 }\n", {},
     "method \"dop853\" does not support measures.basin.period yet"},
    {"dop853_lyapunov", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = 1e-8\n[measures]\nlyapunov = true\n", {},
     "method \"dop853\" does not support measures.lyapunov yet"},
    {"dop853_step_axis", kDw + "[integrator]\nmethod = \"dop853\"\nrtol = 1e-8\n[grid]\nh = { values = [0.01] }\n", {},
     "does not support a grid over h yet"},
    // Wrong types.
    {"scene_name_not_string", "[scene]\nname = 3\n", {},
     "scene.name: expected a string (in quotes), got an integer 3"},
    {"h_string", kDw + "[integrator]\nh = \"0.01\"\n", {},
     "integrator.h: expected a number, got a string \"0.01\""},
    {"parameter_bool", kDw + "gamma = true\n", {},
     "scene.gamma: expected a number, got a boolean true"},
    {"key_lands_in_section_above", kDw + "integrator = 5\n", {}, "unknown key 'scene.integrator'"},
    {"top_section_not_table", "integrator = 5\n" + kDw, {},
     "integrator: expected a table, got an integer 5"},
    {"title_not_string", "title = 3\n" + kDw, {},
     "title: expected a string (in quotes), got an integer 3"},
    {"axis_not_table", kDw + "[grid]\nq_0 = [1, 2]\n", {},
     "grid.q_0: expected a table { from = ..., to = ..., n = ... } or { values = [...] }, got an "
     "array [1, 2]"},
    {"n_float", kDw + "[grid]\nq_0 = { from = 0, to = 1, n = 8.0 }\n", {},
     "grid.q_0.n: expected an integer"},
    {"values_not_array", kDw + "[grid]\nq_0 = { values = 1.0 }\n", {},
     "grid.q_0.values: expected an array"},
    {"values_item_string", kDw + "[grid]\nq_0 = { values = [1.0, \"2\"] }\n", {},
     "grid.q_0.values[1]: expected a number, got a string \"2\""},
    {"every_float", kDw + "[measures]\ntrajectory = { every = 2.5 }\n", {},
     "measures.trajectory.every: expected an integer"},
    {"early_stop_string", kDw + "[measures]\nbasin = { early_stop = \"no\" }\n", {},
     "measures.basin.early_stop: expected true or false, got a string \"no\""},
    {"measure_number", kDw + "[measures]\nbasin = 1\n", {},
     "measures.basin: expected true, false or a table { early_stop, period, tolerance, dwell, "
     "max_period, exact_trap, angles, continuation_threshold, recurrence, cell_size, "
     "recurrences, locate, max_cells, box = ... }, got an integer 1"},
    {"continuation_threshold_zero",
     kDw + "[grid]\ngamma = { values = [0.1, 0.2] }\nq_0 = { from = -1, to = 1, n = 4 }\n"
           "[measures]\nbasin = { continuation_threshold = 0 }\n",
     {}, "measures.basin.continuation_threshold = 0: expected a distance > 0"},
    {"continuation_threshold_without_axis",
     kDw + "[grid]\nq_0 = { from = -1, to = 1, n = 4 }\n"
           "[measures]\nbasin = { continuation_threshold = 0.1 }\n",
     {}, "measures.basin.continuation_threshold: attractors are continued along the grid's first "
         "axis when it sets a scene parameter"},
    {"recurrence_string", kDw + "[measures]\nbasin = { recurrence = \"yes\" }\n", {},
     "measures.basin.recurrence: expected true or false"},
    {"cell_size_zero", kDw + "[measures]\nbasin = { cell_size = 0 }\n", {},
     "measures.basin.cell_size = 0: expected a cell's side > 0"},
    {"recurrences_zero", kDw + "[measures]\nbasin = { recurrences = 0 }\n", {},
     "measures.basin.recurrences = 0: expected an integer >= 1"},
    {"locate_float", kDw + "[measures]\nbasin = { locate = 2.5 }\n", {},
     "measures.basin.locate: expected an integer"},
    {"box_unknown_variable", kDw + "[measures]\nbasin = { box = { pp = [-1, 1] } }\n", {},
     "measures.basin.box.pp: 'pp' is not a position or momentum of scene 'double_well' (q, p)"},
    {"box_reversed", kDw + "[measures]\nbasin = { box = { p = [1, -1] } }\n", {},
     "measures.basin.box.p: expected [lo, hi] with lo < hi"},
    {"vars_not_array", kDw + "[measures]\nfinal_state = { vars = \"q\" }\n", {},
     "measures.final_state.vars: expected an array"},
    // Values out of range, non-finite numbers.
    {"h_negative", kDw + "[integrator]\nh = -0.01\n", {},
     "test.toml:4:5: integrator.h = -0.01: expected a number > 0"},
    {"h_zero", kDw + "[integrator]\nh = 0\n", {}, "integrator.h = 0: expected a number > 0"},
    {"h_nan", kDw + "[integrator]\nh = nan\n", {}, "integrator.h = nan: expected a finite number"},
    {"t_end_inf", kDw + "[integrator]\nt_end = inf\n", {},
     "integrator.t_end = inf: expected a finite number"},
    {"parameter_nan", kDw + "gamma = nan\n", {}, "scene.gamma = nan: expected a finite number"},
    {"initial_inf", kDw + "[initial]\np = -inf\n", {},
     "initial.p = -inf: expected a finite number"},
    {"t_end_negative", kDw + "[integrator]\nt_end = -5\n", {},
     "integrator.t_end = -5: expected a number > 0"},
    {"t_end_shorter_than_h", kDw + "[integrator]\nh = 0.01\nt_end = 0.005\n", {},
     "integrator.t_end = 0.005 is shorter than one step h = 0.01"},
    {"t_end_not_whole_steps", kDw + "[integrator]\nh = 0.01\nt_end = 1.005\n", {},
     "integrator.t_end = 1.005 is not a whole number of steps of h = 0.01 (t_end / h = 100.5); "
     "nearest valid t_end: 1 (100 steps) or 1.01 (101 steps)"},
    {"t_end_default_not_whole_steps", kDw + "[integrator]\nh = 0.03\n", {},
     "nearest valid t_end: 99.99 (3333 steps) or 100.02 (3334 steps)"},
    {"too_many_steps", kDw + "[integrator]\nh = 1e-10\nt_end = 1e10\n", {},
     "integrator.t_end / h = 1e+20 steps: expected at most 2^53"},
    {"lambda_zero", kDw + "[initial]\nlambda = 0\n", {},
     "initial.lambda = 0: expected a number > 0"},
    {"lambda_axis_negative", kDw + "[grid]\nlambda_0 = { from = -1, to = 1, n = 3 }\n", {},
     "grid.lambda_0 = { from = -1, to = 1, n = 3 }: expected values > 0"},
    {"n_zero", kDw + "[grid]\nq_0 = { from = 0, to = 1, n = 0 }\n", {},
     "grid.q_0.n = 0: expected an integer from 1 to 2^32"},
    {"n_too_large", kDw + "[grid]\nq_0 = { from = 0, to = 1, n = 4294967297 }\n", {},
     "grid.q_0.n = 4294967297: expected an integer from 1 to 2^32"},
    {"values_empty", kDw + "[grid]\nq_0 = { values = [] }\n", {},
     "grid.q_0.values = []: expected a non-empty array of numbers"},
    {"values_nan", kDw + "[grid]\np_0 = { values = [0.0, nan] }\n", {},
     "grid.p_0.values[1] = nan: expected a finite number"},
    {"from_inf", kDw + "[grid]\nq_0 = { from = -inf, to = 1, n = 2 }\n", {},
     "grid.q_0.from = -inf: expected a finite number"},
    {"axis_both_forms", kDw + "[grid]\nq_0 = { from = 0, to = 1, n = 2, values = [1] }\n", {},
     "grid.q_0: give either { from, to, n } or { values = [...] }, not both"},
    {"axis_missing_n", kDw + "[grid]\nq_0 = { from = 0, to = 1 }\n", {}, "grid.q_0: missing 'n'"},
    {"axis_empty", kDw + "[grid]\nq_0 = {}\n", {}, "grid.q_0: missing 'from'"},
    {"linspace_overflow", kDw + "[grid]\nq_0 = { from = -1e308, to = 1e308, n = 3 }\n", {},
     "expected from and to whose difference is a finite number"},
    {"grid_too_large", kDw + "[grid]\nq_0 = { from = 0, to = 1, n = 1048576 }\n"
                             "p_0 = { from = 0, to = 1, n = 1048576 }\n"
                             "a = { values = [1, 2] }\n", {},
     "the grid has more than 2^40 = 1099511627776 points (q_0 = 1048576 x p_0 = 1048576 x a = 2)"},
    {"grid_overflow", kDw + "[grid]\nq_0 = { from = 0, to = 1, n = 4294967296 }\n"
                            "p_0 = { from = 0, to = 1, n = 4294967296 }\n"
                            "z_0 = { from = 0, to = 1, n = 4294967296 }\n", {},
     "the grid has more than 2^40"},
    // Measures.
    {"sync_unsupported_a", "[scene]\nname = \"damped_oscillator\"\n[measures]\nsync = {}\n", {},
     "measures.sync: scene 'damped_oscillator' does not support 'sync'; it supports: "
     "final_state, trajectory, basin"},
    {"sync_unsupported", kDw + "[measures]\nsync = { window = [1.0, 2.0] }\n", {},
     "scene 'double_well' does not support 'sync'; it supports: final_state, trajectory, basin"},
    {"vars_unknown", kDw + "[measures]\nfinal_state = { vars = [\"q\", \"q1\"] }\n", {},
     "measures.final_state.vars[1] = \"q1\": expected a variable of scene 'double_well': "
     "q, p, z, lambda"},
    {"vars_twice", kDw + "[measures]\nfinal_state = { vars = [\"q\", \"q\"] }\n", {},
     "measures.final_state.vars[1] = \"q\": expected each variable once"},
    {"vars_empty", kDw + "[measures]\nfinal_state = { vars = [] }\n", {},
     "measures.final_state.vars = []: expected at least one variable"},
    {"every_zero", kDw + "[measures]\ntrajectory = { every = 0 }\n", {},
     "measures.trajectory.every = 0: expected an integer >= 1"},
    {"sync_window_beyond_t_end", kCoupled + "[measures]\nsync = { window = [50.0, 300.0] }\n", {},
     "measures.sync.window = [50.0, 300.0]: expected [from, to] with 0 <= from < to <= "
     "t_end = 200"},
    {"sync_window_reversed", kCoupled + "[measures]\nsync = { window = [100.0, 50.0] }\n", {},
     "0 <= from < to <= t_end"},
    {"sync_window_negative", kCoupled + "[measures]\nsync = { window = [-1.0, 50.0] }\n", {},
     "0 <= from < to <= t_end"},
    {"sync_window_one_number", kCoupled + "[measures]\nsync = { window = [50.0] }\n", {},
     "measures.sync.window = [50.0]: expected two numbers [from, to]"},
    {"sync_window_shorter_than_step",
     kCoupled + "[measures]\nsync = { window = [50.0, 50.001] }\n", {},
     "at least one step h = 0.01 long"},
    {"nothing_requested", kDw + "[measures]\nfinal_state = false\ntrajectory = false\n", {},
     "[measures] requests nothing; scene 'double_well' supports"},
    // --set.
    {"set_without_equals", kDw, {"integrator.h"}, "--set integrator.h: expected KEY=VALUE"},
    {"set_empty_key", kDw, {"=0.1"}, "--set =0.1: empty key before '='"},
    {"set_empty_value", kDw, {"integrator.h="}, "--set integrator.h=: empty value after '='"},
    {"set_bad_key", kDw, {"integrator..h=0.1"},
     "--set integrator..h=0.1: 'integrator..h' is not a dotted key"},
    {"set_not_toml", kDw, {"integrator.h=0.0.1"},
     "--set integrator.h=0.0.1: 0.0.1 is not a TOML value"},
    {"set_through_value", kDw, {"scene.name.x=1"},
     "--set scene.name.x=1: 'scene.name' is a string in the spec, not a table"},
    {"set_two_values", kDw, {"integrator.h=0.1\nt_end = 5"},
     "the value must be a single TOML value"},
    {"set_two_nested_values", kDw, {"integrator.h=0.1\nintegrator.t_end = 5"},
     "the value must be a single TOML value"},
    {"set_unknown_key", kDw, {"integrator.stepsize=0.01"},
     "--set integrator.stepsize=0.01: unknown key 'integrator.stepsize' "
     "(did you mean 'integrator.h'?)"},
    {"set_bad_value", kDw, {"integrator.h=-1"},
     "--set integrator.h=-1: integrator.h = -1: expected a number > 0"},
    {"set_bad_axis", kSweep, {"grid.q_0.n=0"}, "--set grid.q_0.n=0: grid.q_0.n = 0"},
    {"set_n_on_values_axis", kSweep, {"grid.p_0.n=4"},
     "--set grid.p_0.n=4: grid.p_0: give either { from, to, n } or { values = [...] }, not both"},
    {"set_unknown_scene", kDw, {"scene.name=duble_well"},
     "--set scene.name=duble_well: unknown scene \"duble_well\""},
    // A NUL in any string: HDF5 attributes and C strings would cut the text there (issue 22).
    {"nul_in_title", "title = \"map\\u0000hidden\"\n" + kDw, {},
     "title contains a NUL character"},
    {"nul_in_label", "[scene]\nK = \"p^2/2 + q^2/2\"\nlabel = \"osc\\u0000illator\"\n", {},
     "scene.label contains a NUL character"},
    // The literature's s where contactsweep's z (= −s) is meant: said so, with the z name.
    {"s_initial", kDw + "[initial]\ns = 1.0\n", {},
     "unknown key 'initial.s' (contactsweep calls it z (z = −s), so its value changes sign: "
     "did you mean 'initial.z'?)"},
    {"s_axis", kDw + "[grid]\ns_0 = { values = [1.0] }\n", {},
     "unknown key 'grid.s_0' (contactsweep calls it z (z = −s), so its value changes sign: "
     "did you mean 'grid.z_0'?)"},
    {"s_axis_by_set", kDw, {"grid.s_0.values=[1.0]"},
     "--set grid.s_0.values=[1.0]: unknown key 'grid.s_0' (contactsweep calls it z"},
    {"s_final_vars", kDw + "[measures]\nfinal_state = { vars = [\"q\", \"s\"] }\n", {},
     "measures.final_state.vars[1] = \"s\": expected a variable of scene 'double_well': "
     "q, p, z, lambda (contactsweep calls it z (z = −s), so its value changes sign: "
     "did you mean 'z'?)"},
    {"final_s_measure", kDw + "[measures]\nfinal_s = true\n", {},
     "unknown key 'measures.final_s' (contactsweep calls it z (z = −s));"},
    {"s_in_K", "[scene]\nK = \"p^2/2 + q^2/2 + gamma*s\"\ngamma = 0.1\n", {},
     "scene.K: symbol 's' is neither a variable (q, p, z, t, pi) nor a parameter valued in "
     "[scene]: add s = <number> under [scene], or sweep it as a grid axis (contactsweep calls "
     "it z (z = −s), so its value changes sign: did you mean 'z'?)"},
    // A parameter of K neither valued nor swept: both ways out are named.
    {"K_parameter_unvalued", "[scene]\nK = \"p^2/2 + q^2/2 - gamma*z\"\n[grid]\nq_0 = { values = [1.0] }\n",
     {}, "add gamma = <number> under [scene], or sweep it as a grid axis"},
    // The stroboscopic period not a whole number of steps: the largest valid h below is named.
    {"period_not_whole_steps", kDw + "[measures]\nbasin = { period = 1.005 }\n", {},
     "period / h = 100.5 at h = 0.01; choose h = period / N, e.g. h = 0.00995049504950495 "
     "(N = 101)"},
};
// clang-format on

class BadSpecTest : public testing::TestWithParam<BadSpec> {};

// ---- measures as formulas: observe, observe_window, stop (issue 24) --------------------------

TEST(SpecParser, ObserveAndStopAreReadInTheirOrder) {
  const RunSpec spec = parse(kCoupled + R"(
[integrator]
t_end = 50.0
[measures]
observe = { E = "p1^2/2 + p2^2/2", L = "q1*p2 - q2*p1", lam = "lambda*g" }
observe_window = { from = 20.0, to = 50.0 }
stop = { when = "(q1^2 + q2^2 > 4 or p1 > 3) and t >= 1", exits = ["q2 > 0", "q2 <= 0"] }
)");
  ASSERT_TRUE(spec.measures.observe.has_value());
  const auto& f = spec.measures.observe->formulas;
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].first, "E");
  EXPECT_EQ(f[1].second, "q1*p2 - q2*p1");
  EXPECT_EQ(f[2].first, "lam");
  EXPECT_EQ((*spec.measures.observe->window)[0], 20.0);
  EXPECT_EQ(spec.measures.stop->exits.size(), 2u);
  EXPECT_TRUE(spec.measures.stop->label.empty());
  // [measures] with only observe asks for nothing else
  EXPECT_FALSE(spec.measures.final_state.has_value());
}

TEST(SpecParser, BadObserveAndStopAreNamed) {
  const std::string base = kDoubleWell + "[integrator]\nt_end = 10.0\n[measures]\n";
  expect_input_error(base + "observe = { E = \"p^2/2 + omega*q\" }",
                     "measures.observe.E: 'p^2/2 + omega*q' reads 'omega', which is not a symbol "
                     "of scene 'double_well'");
  expect_input_error(base + "observe = { E = \"q1\" }", "reads 'q1'");
  expect_input_error(base + "observe = { H = \"p^2\" }", "measures.observe.H: 'H' would name");
  expect_input_error(base + "observe = { q = \"p^2\" }", "measures.observe.q: 'q' would name");
  expect_input_error(base + "observe = { E = \"p^2 +\" }", "measures.observe.E: 'p^2 +' syntax error");
  expect_input_error(base + "observe = { E = \"\" }", "measures.observe.E: an empty formula");
  expect_input_error(base + "observe = { E = 3 }", "measures.observe.E");
  expect_input_error(base + "observe = {}", "measures.observe");
  expect_input_error(base + "observe = { E = \"p\" }\nobserve_window = { from = 5.0, to = 11.0 }",
                     "measures.observe_window = { from = 5, to = 11 }: expected 0 <= from <= to "
                     "<= t_end = 10");
  expect_input_error(base + "observe = { E = \"p\" }\nobserve_window = { from = 5.0 }",
                     "give both ends");
  expect_input_error(base + "observe_window = { from = 1.0, to = 2.0 }\nfinal_state = true",
                     "give measures.observe");
  expect_input_error(base + "stop = { when = \"q^2 + p^2\" }", "is not a comparison");
  expect_input_error(base + "stop = { when = \"q > 1 and\" }", "without a comparison");
  expect_input_error(base + "stop = { when = \"q == 1\" }", "compares with <, <=, > or >=");
  expect_input_error(base + "stop = { when = \"0 < q < 1\" }", "chains comparisons");
  expect_input_error(base + "stop = { when = \"(q > 1\" }", "never closed");
  expect_input_error(base + "stop = { when = \"q > 1 and not p > 0\" }", "'not'");
  expect_input_error(base + "stop = { when = \"q > w\" }", "measures.stop.when: 'w' reads 'w', which is not a symbol");
  expect_input_error(base + "stop = { when = \"q > 1 +\" }",
                     "measures.stop.when: '1 +' syntax error at column 7");
  expect_input_error(base + "stop = { label = \"1\" }", "give the condition");
  expect_input_error(base + "stop = { when = \"q > 1\", label = \"1\", exits = [\"q > 0\"] }",
                     "not both");
  expect_input_error(base + "stop = { when = \"q > 1\", exits = [\"q\"] }",
                     "measures.stop.exits[0]");
  expect_input_error(base + "stop = { when = \"q > 1\", colour = 1 }", "measures.stop");
}

TEST_P(BadSpecTest, IsRefusedWithAMessageNamingTheProblem) {
  const BadSpec& bad = GetParam();
  const std::string message = message_of(bad.text, bad.overrides);
  EXPECT_NE(message.find(bad.fragment), std::string::npos)
      << "message: " << message << "\nexpected fragment: " << bad.fragment;
  EXPECT_TRUE(message.starts_with("test.toml") || message.starts_with("--set ")) << message;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadSpecTest, testing::ValuesIn(kBadSpecs),
                         [](const testing::TestParamInfo<BadSpec>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace cs
