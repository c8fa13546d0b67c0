// The spec parser's refusals: a corpus of bad inputs, each of which must raise an InputError whose
// message names what is wrong and where (the file position or the --set argument); and the
// measures as formulas' own (observe, observe_window, stop).
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/spec_parser.hpp"
#include "support/spec_parsing.hpp"

namespace cs {
namespace {

using namespace test;  // parse, message_of, expect_input_error, kDoubleWell, kCoupled, kSweep

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
