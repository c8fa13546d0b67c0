#include "engine/run_plan.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include <fmt/format.h>

#include "engine/attractor_table.hpp"
#include "physics/energy_wells.hpp"  // kTrapVerdicts

namespace cs {
namespace {

std::string dataset_variable(const std::string& var) {
  return var == "lambda" ? "log_lambda" : var;
}

std::string variable_long_name(const VariableInfo& v) {
  return v.name == "lambda" ? "ln lambda (log of the integration factor)" : v.description;
}

bool wants(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

// Steps between looks at the lanes: long enough that looking costs little next to stepping
// (32 steps: the look costs ~3 % of a chunk, at 16 it cost 12 % more instructions), short
// enough for a prompt early stop and a settle_time resolved to 32 h; always a divisor of the
// trajectory sampling interval and of the stroboscopic period, so that samples fall on looks
// (a fixed-step method's: an adaptive method's samples fall inside its steps).
// Synchronization is sampled on looks, which must be close enough (≤ 0.2 time units) for the
// phases to be unwrapped unambiguously and to resolve the oscillations.
int choose_chunk(const RunSpec& spec) {
  std::int64_t cap = 32;
  if (spec.measures.sync)
    cap = std::clamp<std::int64_t>(static_cast<std::int64_t>(0.2 / spec.h), 1, 32);
  std::int64_t multiple_of = 0;  // every interval the chunk must divide: their gcd
  // An adaptive method's samples are interpolated where they fall, not taken at looks.
  const MethodInfo* method = find_method(spec.method);
  const bool adaptive = method != nullptr && method->adaptive;
  if (spec.measures.trajectory && !adaptive) multiple_of = spec.measures.trajectory->every;
  if (spec.measures.basin && spec.measures.basin->period && !adaptive)
    multiple_of = std::gcd(multiple_of, std::llround(*spec.measures.basin->period / spec.h));
  if (multiple_of == 0) return static_cast<int>(cap);
  for (std::int64_t c = std::min<std::int64_t>(multiple_of, cap); c > 1; --c)
    if (multiple_of % c == 0) return static_cast<int>(c);
  return 1;
}

}  // namespace

RunPlan::RunPlan(const RunSpec& s, const SceneInfo& sc, const MethodInfo& m)
    : spec(s), scene(sc), method(m), grid(s, sc) {
  const auto& measures = spec.measures;
  const auto nvars = scene.variables.size();
  chunk = choose_chunk(spec);
  map.final_vars.assign(nvars, -1);
  map.traj_vars.assign(nvars, -1);
  auto add = [&](DatasetSpec d, std::int64_t width = 1) { return add_column(std::move(d), width); };

  // A cell no rank wrote must never read as "ok": sweep.cpp checks that every point was
  // computed before it writes, and the file's fill value says not_computed besides.
  map.status = add({"status", ElementType::uint8, false, "integration status", "",
                    {0, 1, 2, 3, 4, kStatusNotComputed},
                    "ok diverged integrator_breakdown non_finite_output k_undefined_at_start "
                    "not_computed",
                    std::nullopt,
                    kStatusNotComputed});

  if (measures.final_state) {
    const auto& vars = measures.final_state->vars;
    for (std::size_t i = 0; i < nvars; ++i) {
      const auto& v = scene.variables[i];
      if (!wants(vars, v.name)) continue;
      map.final_vars[i] = add({"final_" + dataset_variable(v.name), ElementType::float64, false,
                               variable_long_name(v) + " at t_end", "", {}, "", std::nullopt});
    }
    if (wants(vars, "z") && wants(vars, "lambda")) {
      map.final_H = add({"final_H", ElementType::float64, false,
                         "H = lambda*K at t_end (conserved by the exact flow)", "", {}, "",
                         std::nullopt});
    }
    carry.z = wants(vars, "z") || map.final_H >= 0;
    carry.mu = wants(vars, "lambda");
  }

  if (measures.trajectory) {
    auto every = measures.trajectory->every;
    samples = spec.steps / every + 1;
    // An adaptive method's steps are nominal (t_end / h rounded): its samples are the times
    // t_start + k·every·h up to t_end (a hair's rounding beyond it taking the state at t_end).
    if (const MethodInfo* m = find_method(spec.method); m != nullptr && m->adaptive) {
      const double slack = 1e-12 * (spec.t_end - spec.t_start);
      while (samples > 1 && spec.t_start + static_cast<double>((samples - 1) * every) * spec.h >
                                spec.t_end + slack)
        --samples;
    }
    for (std::int64_t k = 0; k < samples; ++k)
      sample_times.push_back(spec.t_start + static_cast<double>(k * every) * spec.h);
    for (std::size_t i = 0; i < nvars; ++i) {
      const auto& v = scene.variables[i];
      map.traj_vars[i] = add({"traj_" + dataset_variable(v.name), ElementType::float64, true,
                              variable_long_name(v), "", {}, "", std::nullopt},
                             samples);
    }
    map.traj_H = add({"traj_H", ElementType::float64, true, "H = lambda*K", "", {}, "",
                      std::nullopt},
                     samples);
    carry.z = carry.mu = true;
  }

  if (measures.basin) add_basin_columns(*measures.basin);

  if (measures.lyapunov) {
    // Its interval (docs/lyapunov.md): the run's (said only where it could be another), or
    // observe_window's, cut short by a stop.
    std::string over;
    if (measures.observe && measures.observe->window)
      over = fmt::format(" over the steps of observe_window [{}, {}]",
                         (*measures.observe->window)[0], (*measures.observe->window)[1]);
    else if (measures.stop)
      over = " over [t_start, t_end]";
    if (measures.stop) over += " or until the stop";
    map.lyapunov = add({"lyapunov", ElementType::float64, false,
                        "finite-time largest Lyapunov exponent of the integrator's step map" + over,
                        "1/time", {}, "", std::nullopt});
    const auto& vars = measures.lyapunov->vars;
    for (int k = 0; k <= 2 * scene.dof; ++k)  // q.., p.., z: the catalog's order
      lyapunov_seed.push_back(wants(vars, scene.variables[static_cast<std::size_t>(k)].name));
    lyapunov_log_norm0 = 0.5 * std::log(static_cast<double>(vars.size()));
    carry.tangent = true;
  }

  if (measures.sync) {
    // The window's ends, rounded inwards to the looks at the lanes.
    const double from = measures.sync->window_from - spec.t_start;
    const double to = measures.sync->window_to - spec.t_start;
    auto first = static_cast<std::int64_t>(std::ceil(from / spec.h - 1e-9));
    auto last = static_cast<std::int64_t>(std::floor(to / spec.h + 1e-9));
    sync_first_step = (first + chunk - 1) / chunk * chunk;
    sync_last_step = last / chunk * chunk;
    // One look would give a phase-locking value of 1 and no frequencies: meaningless numbers.
    if (sync_last_step <= sync_first_step)
      throw InputError(fmt::format(
          "measures.sync.window = [{}, {}] holds fewer than two looks at the lanes, which come "
          "every {} time units at h = {}: expected a window at least {} long",
          measures.sync->window_from, measures.sync->window_to, chunk * spec.h, spec.h,
          2 * chunk * spec.h));
    map.sync_r = add({"sync_r", ElementType::float64, false,
                      "phase-locking value |<exp(i(theta1-theta2))>| over the window", "", {}, "",
                      std::nullopt});
    map.sync_phase_drift = add({"sync_phase_drift", ElementType::float64, false,
                                "mean rate of the unwrapped phase difference over the window",
                                "rad/time", {}, "", std::nullopt});
    map.sync_freq_ratio = add({"sync_freq_ratio", ElementType::float64, false,
                               "measured frequency ratio omega1/omega2 over the window (NaN "
                               "where oscillator 2 is at rest: sync_amplitude = 0)",
                               "", {}, "", std::nullopt});
    map.sync_amplitude = add({"sync_amplitude", ElementType::float64, false,
                              "smaller oscillator amplitude at the window's end", "", {}, "",
                              std::nullopt});
  }
  plan_observables(*this);
  // An adaptive method steers its steps by the error of everything it integrates: z and ln λ
  // are in its error norm whatever the run writes, so that they are as accurate as q and p and
  // a lane's steps (its q and p bits) do not depend on which outputs were asked for.
  if (method.adaptive) carry.z = carry.mu = true;
}

int RunPlan::add_column(DatasetSpec dataset, std::int64_t width, bool internal) {
  columns.push_back({std::move(dataset), width, internal});
  return static_cast<int>(columns.size() - 1);
}

void RunPlan::add_basin_columns(const BasinMeasure& basin) {
  auto add = [&](DatasetSpec d, std::int64_t width = 1, bool internal = false) {
    return add_column(std::move(d), width, internal);
  };
  // Up to one attractor per point, each with its own label: checked here, before any work.
  if (grid.size() > kMaxAttractors)
    throw InputError(fmt::format("measures.basin: a basin map of {} points has more cells than "
                                 "the {} labels an int32 holds; use a coarser grid",
                                 grid.size(), kMaxAttractors));
  // The scene's label rule decides what the labels mean (label_rule.hpp); should it not apply
  // to the attractors found, the file says so and the flags go (BasinSummary::labels).
  const LabelRule& rule = scene.label_rule;
  // A stop's exits are outcomes of their own, numbered with the attractors (observe_plan.hpp).
  if (rule.kind == LabelRule::Kind::sign_of_q1 && !spec.measures.stop)
    map.basin = add({"basin", ElementType::int8, false, "basin of attraction", "", {-1, 0, 1},
                     rule.negative + " undecided " + rule.positive, std::nullopt});
  else
    map.basin = add({"basin", ElementType::int8, false, kNumberedBasinLongName, "", {}, "",
                     std::nullopt});
  map.settle_time = add({"settle_time", ElementType::float64, false,
                         "time from which the lane stayed near its attractor", "time", {}, "",
                         std::nullopt});
  const int phase_space = 2 * scene.dof;
  // Whether the energy trap (energy_wells.hpp) served the lanes, and if not why: the kernel
  // alone can tell (it evaluates V), so each block counts its lanes' verdicts, one count per
  // TrapVerdict (BasinSummary::energy_trap). Per block, not per point: a verdict depends on the
  // lane's parameters alone, so a whole map mostly has one; a column per point cost 1–2 % of
  // the double well's map (zeroed, copied, journalled).
  if (basin.exact_trap) {
    map.trap_verdict = add({"trap_verdict", ElementType::float64, false, "", "", {}, "",
                            std::nullopt},
                           kTrapVerdicts, true);
    columns.back().per_block = true;
  }
  // Where settled lanes settled: per block, each distinct (point.., period) once; a settled
  // lane's provisional `basin` value numbers its record (SettlementRecords). Lanes of a map
  // mostly share a few points (the energy trap's minima, exact): a (point, period) per lane
  // cost the double well's map 6 MB zeroed, written, checksummed and journalled (+20 % time).
  map.basin_records = add({"basin_records", ElementType::float64, false, "", "", {}, "",
                           std::nullopt},
                          phase_space + 1, true);
  columns.back().per_block = columns.back().grows = true;
  AttractorSearch& a = attractors;
  a.tolerance = basin.tolerance;
  a.max_period = basin.max_period;
  a.sample_steps = basin.period ? std::llround(*basin.period / spec.h) : chunk;
  double sample_time = static_cast<double>(a.sample_steps) * spec.h;
  if (basin.period && method.adaptive) {
    a.dense_strobe = true;
    a.sample_steps = 1;
    sample_time = *basin.period;
    // The last k with t_start + k·period ≤ t_end, a hair's rounding beyond it counted in (that
    // sample takes the state at t_end, as a trajectory's does).
    const double span = spec.t_end - spec.t_start, slack = 1e-12 * span;
    a.strobe_last = static_cast<std::int64_t>(std::floor((span + slack) / *basin.period));
    while (a.strobe_last > 0 &&
           spec.t_start + static_cast<double>(a.strobe_last) * *basin.period > spec.t_end + slack)
      --a.strobe_last;
  }
  a.dwell_samples = static_cast<int>(
      std::clamp(std::ceil(basin.dwell / sample_time - 1e-9), 1.0, 1e9));
  a.angle_period.assign(static_cast<std::size_t>(phase_space), 0.0);
  for (int k = 0; k < phase_space; ++k) {
    auto it = basin.angles.find(scene.variables[static_cast<std::size_t>(k)].name);
    if (it != basin.angles.end()) a.angle_period[static_cast<std::size_t>(k)] = it->second;
  }
  recurrence = plan_recurrence(spec, scene, a.angle_period);
  if (recurrence.enabled) {
    map.basin_cells = add({"basin_cells", ElementType::float64, false, "", "", {}, "", std::nullopt},
                          RecurrenceSearch::kRecordWidth, true);
    map.undecided_reason = add(
        {"undecided_reason", ElementType::float64, false, "", "", {}, "", std::nullopt}, 1, true);
  }
}

std::vector<std::unique_ptr<RunPlan>> step_size_slices(const RunSpec& spec, const SceneInfo& scene,
                                                       const MethodInfo& method,
                                                       std::vector<std::unique_ptr<RunSpec>>& specs) {
  std::vector<std::unique_ptr<RunPlan>> plans;
  if (spec.axes.empty() || !spec.axes.front().is_step_size) {
    plans.push_back(std::make_unique<RunPlan>(spec, scene, method));
    return plans;
  }
  std::int64_t slice_points = 1;
  for (std::size_t a = 1; a < spec.axes.size(); ++a)
    slice_points *= static_cast<std::int64_t>(spec.axes[a].values.size());
  const auto& hs = spec.axes.front().values;
  for (std::size_t i = 0; i < hs.size(); ++i) {
    auto slice = std::make_unique<RunSpec>(spec);
    slice->h = hs[i];
    slice->steps = std::llround((spec.t_end - spec.t_start) / hs[i]);  // whole: checked
    slice->axes.erase(slice->axes.begin());
    plans.push_back(std::make_unique<RunPlan>(*slice, scene, method));
    plans.back()->point_offset = static_cast<std::int64_t>(i) * slice_points;
    specs.push_back(std::move(slice));
  }
  return plans;
}

}  // namespace cs
