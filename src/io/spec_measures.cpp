// [measures]: final_state, trajectory, basin and sync, each checked against the scene.
#include "io/spec_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string>

#include "io/spec_suggestions.hpp"
#include "numerics/method_catalog.hpp"

namespace cs::spec {

void SpecReader::read_measures() {
  const toml::node* node = doc_.get("measures");
  if (node == nullptr) {
    spec_.measures.final_state = FinalStateMeasure{variable_names(*scene_)};
    return;
  }
  const toml::table& t = table(*node, "measures");
  check_keys(t, "measures", Names(std::begin(kMeasureNames), std::end(kMeasureNames)));
  read_final_state(t);
  read_trajectory(t);
  read_basin(t);
  read_sync(t);
  read_lyapunov(t);
  read_observe(t);
  read_stop(t);
  const Measures& m = spec_.measures;
  if (!m.final_state && !m.trajectory && !m.basin && !m.sync && !m.lyapunov && !m.observe && !m.stop)
    fail(node, fmt::format("[measures] requests nothing; scene '{}' supports: {}", scene_->name,
                           fmt::join(scene_->measures, ", ")));
}

const toml::table* SpecReader::measure_settings(const toml::table& measures, std::string_view name,
                                    const Names& keys) const {
  static const toml::table defaults;
  const toml::node* node = measures.get(name);
  if (node == nullptr) return nullptr;
  const std::string key = fmt::format("measures.{}", name);
  const toml::table* settings = &defaults;
  if (const auto* b = node->as_boolean()) {
    if (!b->get()) return nullptr;
  } else if (node->is_table()) {
    settings = node->as_table();
  } else {
    fail_type(*node, key,
              fmt::format("true, false or a table {{ {} = ... }}", fmt::join(keys, ", ")));
  }
  if (!contains(scene_->measures, name))
    fail(node, fmt::format("{}: scene '{}' does not support '{}'; it supports: {}", key,
                           scene_->name, name, fmt::join(scene_->measures, ", ")));
  check_keys(*settings, key, keys);
  return settings;
}

void SpecReader::read_final_state(const toml::table& measures) {
  const toml::table* t = measure_settings(measures, "final_state", {"vars"});
  if (t == nullptr) return;
  const Names all = variable_names(*scene_);
  const toml::node* vars = t->get("vars");
  if (vars == nullptr) {
    spec_.measures.final_state = FinalStateMeasure{all};
    return;
  }
  const toml::array& list = array(*vars, "measures.final_state.vars");
  if (list.empty())
    fail_value(*vars, "measures.final_state.vars",
               "at least one variable (or final_state = false)");
  Names chosen;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = fmt::format("measures.final_state.vars[{}]", i);
    const std::string var = string(*list.get(i), key);
    if (!contains(all, var))
      fail_value(*list.get(i), key,
                 fmt::format("a variable of scene '{}': {}{}", scene_->name, fmt::join(all, ", "),
                             contact_variable_hint(var, all, "").empty()
                                 ? did_you_mean(var, all, "")
                                 : contact_variable_hint(var, all, "")));
    if (contains(chosen, var)) fail_value(*list.get(i), key, "each variable once");
    chosen.push_back(var);
  }
  Names in_scene_order;
  for (const std::string& var : all)
    if (contains(chosen, var)) in_scene_order.push_back(var);
  spec_.measures.final_state = FinalStateMeasure{in_scene_order};
}

void SpecReader::read_trajectory(const toml::table& measures) {
  const toml::table* t = measure_settings(measures, "trajectory", {"every"});
  if (t == nullptr) return;
  TrajectoryMeasure trajectory;
  if (const toml::node* every = t->get("every")) {
    trajectory.every = integer(*every, "measures.trajectory.every");
    if (trajectory.every < 1)
      fail_value(*every, "measures.trajectory.every", "an integer >= 1 (steps between samples)");
  }
  if (!spec_.axes.empty() && spec_.axes.front().is_step_size)
    fail(measures.get("trajectory"), "measures.trajectory cannot be combined with a grid over h "
                                     "(the time axis would differ from one h to the next)");
  spec_.measures.trajectory = trajectory;
}

void SpecReader::read_basin(const toml::table& measures) {
  const toml::table* t = measure_settings(
      measures, "basin",
      {"early_stop", "period", "tolerance", "dwell", "max_period", "exact_trap", "angles",
       "continuation_threshold", "recurrence", "cell_size", "recurrences", "locate", "max_cells",
       "box"});
  if (t == nullptr) return;
  BasinMeasure basin;
  if (const toml::node* early_stop = t->get("early_stop"))
    basin.early_stop = boolean(*early_stop, "measures.basin.early_stop");
  if (const toml::node* exact_trap = t->get("exact_trap"))
    basin.exact_trap = boolean(*exact_trap, "measures.basin.exact_trap");
  if (const toml::node* period = t->get("period")) read_basin_period(*period, basin);
  if (const toml::node* tolerance = t->get("tolerance")) {
    basin.tolerance = number(*tolerance, "measures.basin.tolerance");
    if (!(basin.tolerance > 0.0))
      fail_value(*tolerance, "measures.basin.tolerance",
                 "a distance > 0 (max norm over q and p)");
  }
  basin.dwell = basin.period ? BasinMeasure::kDefaultDwellPeriods * *basin.period
                             : BasinMeasure::kDefaultDwell;
  if (const toml::node* dwell = t->get("dwell")) {
    basin.dwell = number(*dwell, "measures.basin.dwell");
    if (!(basin.dwell > 0.0))
      fail_value(*dwell, "measures.basin.dwell",
                 "a time > 0 (how long a lane must stay near its attractor)");
  }
  if (basin.period) basin.max_period = BasinMeasure::kDefaultMaxPeriod;
  if (const toml::node* max_period = t->get("max_period")) {
    const std::int64_t m = integer(*max_period, "measures.basin.max_period");
    if (!basin.period && m != 1)
      fail(max_period, "measures.basin.max_period: cycles are looked for on the stroboscopic "
                       "map only; give measures.basin.period (the forcing period) too");
    if (m < 1 || m > BasinMeasure::kMaxPeriodLimit)
      fail_value(*max_period, "measures.basin.max_period",
                 fmt::format("an integer from 1 to {}", BasinMeasure::kMaxPeriodLimit));
    basin.max_period = static_cast<int>(m);
  }
  if (const toml::node* angles = t->get("angles")) {
    const toml::table& list = table(*angles, "measures.basin.angles");
    Names phase_space;
    for (const auto& v : scene_->variables)
      if (v.name != "z" && v.name != "lambda") phase_space.push_back(v.name);
    for (const auto& [name, value] : list) {
      const std::string key = fmt::format("measures.basin.angles.{}", name.str());
      if (!contains(phase_space, std::string(name.str())))
        fail(&value, fmt::format("{}: '{}' is not a position or momentum of scene '{}' ({}){}",
                                 key, name.str(), scene_->name, fmt::join(phase_space, ", "),
                                 did_you_mean(std::string(name.str()), phase_space, "")));
      const double angle_period = number(value, key);
      if (!(angle_period > 0.0))
        fail_value(value, key, "the variable's period > 0 (e.g. 6.283185307179586)");
      basin.angles[std::string(name.str())] = angle_period;
    }
  }
  if (const toml::node* threshold = t->get("continuation_threshold"))
    basin.continuation_threshold = read_continuation_threshold(*threshold);
  read_basin_recurrence(*t, basin.recurrence);
  spec_.measures.basin = basin;
}

double SpecReader::read_continuation_threshold(const toml::node& node) {
  const std::string key = "measures.basin.continuation_threshold";
  if (spec_.axes.size() < 2 || !spec_.axes.front().is_parameter)
    fail(&node, key + ": attractors are continued along the grid's first axis when it sets a "
                      "scene parameter and other axes follow; this grid's does not");
  const double threshold = number(node, key);
  if (!(threshold > 0.0))
    fail_value(node, key,
               "a distance > 0 (max norm over q and p): how far an attractor may move between "
               "neighbouring values and keep its label");
  return threshold;
}

void SpecReader::read_basin_period(const toml::node& node, BasinMeasure& basin) {
  const std::string key = "measures.basin.period";
  const double period = number(node, key);
  if (!(period > 0.0)) fail_value(node, key, "the forcing period > 0");
  std::vector<double> hs{spec_.h};
  if (!spec_.axes.empty() && spec_.axes.front().is_step_size) hs = spec_.axes.front().values;
  // An adaptive method samples the map at t_start + k·period from its steps' dense output:
  // its h (the first step) need not divide the period.
  if (find_method(spec_.method)->adaptive) hs.clear();
  for (double h : hs) {
    const double ratio = period / h;
    const auto steps = std::llround(ratio);
    if (steps < 1 || std::abs(static_cast<double>(steps) * h - period) > kStepTolerance * period) {
      // The largest h' <= h with a whole number of steps per period.
      const double n = std::max(1.0, std::ceil(ratio - kStepTolerance * ratio));
      fail(&node, fmt::format("{} = {}: the stroboscopic map needs a whole number of steps per "
                              "period, but period / h = {:.12g} at h = {}; choose h = period / N, "
                              "e.g. h = {:.15g} (N = {:.0f})",
                              key, period, ratio, h, period / n, n));
    }
  }
  basin.period = period;
}

void SpecReader::read_sync(const toml::table& measures) {
  const toml::table* t = measure_settings(measures, "sync", {"window", "dof", "omega"});
  if (t == nullptr) return;
  SyncMeasure sync;  // the second half of the run by default
  sync.window_from = spec_.t_start + (spec_.t_end - spec_.t_start) / 2.0;
  sync.window_to = spec_.t_end;
  read_sync_pair(*t, sync);
  if (const toml::node* window = t->get("window")) {
    const std::string key = "measures.sync.window";
    const std::vector<double> ends = numbers(*window, key);
    if (ends.size() != 2) fail_value(*window, key, "two numbers [from, to]");
    if (!(spec_.t_start <= ends[0] && ends[0] < ends[1] && ends[1] <= spec_.t_end))
      fail_value(*window, key,
                 fmt::format("[from, to] with {} <= from < to <= t_end = {}",
                             spec_.t_start == 0.0 ? std::string("0")
                                                  : fmt::format("t_start = {}", spec_.t_start),
                             spec_.t_end));
    if (ends[1] - ends[0] < spec_.h)
      fail_value(*window, key, fmt::format("a window at least one step h = {} long", spec_.h));
    sync.window_from = ends[0], sync.window_to = ends[1];
  }
  spec_.measures.sync = sync;
}

void SpecReader::read_sync_pair(const toml::table& t, SyncMeasure& sync) {
  if (const toml::node* dof = t.get("dof")) {
    const std::string key = "measures.sync.dof";
    const toml::array& list = array(*dof, key);
    const int n = scene_->dof;
    if (list.size() != 2) fail_value(*dof, key, "two degrees of freedom [i, j], counted from 1");
    for (std::size_t k = 0; k < 2; ++k) {
      const std::int64_t i = integer(*list.get(k), fmt::format("{}[{}]", key, k));
      if (i < 1 || i > n)
        fail_value(*list.get(k), fmt::format("{}[{}]", key, k),
                   fmt::format("a degree of freedom of scene '{}', from 1 to {}", scene_->name, n));
      sync.dof[k] = static_cast<int>(i - 1);
    }
    if (sync.dof[0] == sync.dof[1]) fail_value(*dof, key, "two different degrees of freedom");
  }
  if (const toml::node* omega = t.get("omega")) {
    const std::string key = "measures.sync.omega";
    const std::vector<double> w = numbers(*omega, key);
    if (w.size() != 2 || !(w[0] > 0.0) || !(w[1] > 0.0))
      fail_value(*omega, key, "two frequencies > 0 [omega_i, omega_j] that scale p_i and p_j");
    sync.omega = std::array<double, 2>{w[0], w[1]};
  }
}

}  // namespace cs::spec
