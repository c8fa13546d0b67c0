#include "engine/measures/observe_plan.hpp"

#include <cmath>

#include <fmt/format.h>

#include "engine/run_plan.hpp"
#include "formula/measure_formulas.hpp"

namespace cs {

void plan_observables(RunPlan& plan) {
  const Measures& m = plan.spec.measures;
  if (!has_measure_formulas(m)) return;
  ObservePlan& o = plan.observe;
  const FormulaReads reads = measure_formula_reads(m, plan.scene);
  if (reads.z) plan.carry.z = true;
  if (reads.lambda) plan.carry.mu = true;
  auto add = [&](DatasetSpec d, std::int64_t width = 1) {
    return plan.add_column(std::move(d), width);
  };
  const RunSpec& spec = plan.spec;
  if (m.observe) {
    o.observables = static_cast<int>(m.observe->formulas.size());
    const std::string at_end = m.stop ? " at t_end, or at the stop" : " at t_end";
    for (const auto& [name, text] : m.observe->formulas)
      o.final_value.push_back(add({"final_" + name, ElementType::float64, false,
                                   name + " = " + text + at_end, "", {}, "", std::nullopt}));
    for (const auto& [name, text] : m.observe->formulas)
      o.trajectory.push_back(plan.samples > 0
                                 ? add({"traj_" + name, ElementType::float64, true,
                                        name + " = " + text, "", {}, "", std::nullopt},
                                       plan.samples)
                                 : -1);
    if (m.observe->window) {
      o.window = true;
      o.window_every_step = plan.samples == 0;
      const auto [from, to] = *m.observe->window;
      // The window's ends in steps, rounded inwards (as sync's window).
      const auto first = static_cast<std::int64_t>(std::ceil((from - spec.t_start) / spec.h - 1e-9));
      const auto last = static_cast<std::int64_t>(std::floor((to - spec.t_start) / spec.h + 1e-9));
      std::int64_t every = o.window_every_step ? 1 : m.trajectory->every;
      o.window_first = (std::max<std::int64_t>(first, 0) + every - 1) / every * every;
      o.window_last = std::min(last, spec.steps) / every * every;
      if (o.window_last < o.window_first)
        throw InputError(fmt::format(
            "measures.observe_window = {{ from = {}, to = {} }} holds no sample: samples come "
            "every {} time units ({}); widen the window",
            from, to, static_cast<double>(every) * spec.h,
            o.window_every_step
                ? fmt::format("every step of h = {}, no trajectory", spec.h)
                : fmt::format("trajectory.every = {} steps of h = {}", every, spec.h)));
      const std::string window = fmt::format(" over t in [{}, {}] ({} samples at most)", from, to,
                                             (o.window_last - o.window_first) / every + 1);
      for (const auto& [name, text] : m.observe->formulas) {
        o.mean.push_back(add({"mean_" + name, ElementType::float64, false,
                              "mean of " + name + window, "", {}, "", std::nullopt}));
        o.min.push_back(add({"min_" + name, ElementType::float64, false,
                             "minimum of " + name + window, "", {}, "", std::nullopt}));
        o.max.push_back(add({"max_" + name, ElementType::float64, false,
                             "maximum of " + name + window, "", {}, "", std::nullopt}));
      }
    }
  }
  if (m.stop) {
    o.stop = true;
    o.stop_time = add({"stop_time", ElementType::float64, false,
                       "time at the end of the first step where " + m.stop->when +
                           " (NaN: never)",
                       "time", {}, "", std::nullopt});
    o.exits = !m.stop->label.empty() || !m.stop->exits.empty();
    if (o.exits)
      o.stop_exit = add({"stop_exit", ElementType::int16, false,
                         "exit channel of the stop (1, 2, ...; 0: no stop, or no channel)", "",
                         {}, "", std::nullopt});
  }
}

}  // namespace cs
