// [integrator]: the method, the step h, t_start and t_end, and t_end as a whole number of steps;
// an adaptive method's tolerances rtol and atol (its h: the first step each lane tries).
#include "io/spec_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "io/spec_suggestions.hpp"
#include "io/spec_text.hpp"
#include "numerics/method_catalog.hpp"

namespace cs::spec {

namespace {

constexpr std::string_view kDefaultMethod = "hybrid_leapfrog";

}  // namespace

void SpecReader::read_integrator() {
  const toml::table& t = section("integrator");
  check_keys(t, "integrator", {"method", "h", "t_end", "t_start", "rtol", "atol"});
  read_method(t);
  const bool adaptive = find_method(spec_.method)->adaptive;
  spec_.h = number_or(t, "integrator", "h", scene_->default_h);
  spec_.t_start = number_or(t, "integrator", "t_start", 0.0);
  spec_.t_end = number_or(t, "integrator", "t_end", spec_.t_start + scene_->default_t_end);
  if (!(spec_.h > 0.0)) fail_value(*t.get("h"), "integrator.h", "a number > 0");
  if (!std::isfinite(spec_.t_start))
    fail_value(*t.get("t_start"), "integrator.t_start", "a finite number");
  if (spec_.t_start == 0.0 && !(spec_.t_end > 0.0))
    fail_value(*t.get("t_end"), "integrator.t_end", "a number > 0");
  if (!(spec_.t_end > spec_.t_start))
    fail(t.get("t_end") != nullptr ? t.get("t_end") : t.get("t_start"),
         fmt::format("integrator.t_end = {} is not after integrator.t_start = {}", spec_.t_end,
                     spec_.t_start));
  if (adaptive) {
    read_tolerances(t);
    const double ratio = (spec_.t_end - spec_.t_start) / spec_.h;
    if (!(ratio <= kMaxSteps))
      fail(t.get("h"), fmt::format("integrator.{} / h = {:.6g}: expected at most 2^53",
                                   duration_name(), ratio));
    spec_.steps = std::max<std::int64_t>(1, std::llround(ratio));  // nominal: sizes blocks
    return;
  }
  for (const char* key : {"rtol", "atol"})
    if (const toml::node* node = t.get(key))
      fail(node, fmt::format("integrator.{} is a tolerance of an adaptive method (dop853); "
                             "method {} steps at the fixed h",
                             key, toml_string(spec_.method)));
  spec_.steps = whole_steps(t.get("t_end") != nullptr ? t.get("t_end") : t.get("h"));
}

// rtol (required: no default tolerance serves every scene) and atol (default: rtol), both > 0
// and finite.
void SpecReader::read_tolerances(const toml::table& t) {
  const toml::node* rtol = t.get("rtol");
  if (rtol == nullptr)
    fail(t.get("method"), fmt::format("method {} is adaptive: integrator.rtol (its relative "
                                      "tolerance, e.g. 1e-8) is required",
                                      toml_string(spec_.method)));
  spec_.rtol = number(*rtol, "integrator.rtol");
  if (!(spec_.rtol > 0.0) || !std::isfinite(spec_.rtol))
    fail_value(*rtol, "integrator.rtol", "a finite number > 0");
  spec_.atol = number_or(t, "integrator", "atol", spec_.rtol);
  if (!(spec_.atol > 0.0) || !std::isfinite(spec_.atol))
    fail_value(*t.get("atol"), "integrator.atol", "a finite number > 0");
}

// What an adaptive method does not do yet, refused by name. Its lanes step to times of their
// own; the samples of a trajectory, its observables, sync, the stroboscopic map, an
// observe_window's every nominal step and the stop's time between two steps come from the
// step's dense output (numerics/dop853_dense.hpp), as does lyapunov's tangent at a stop and at
// an observe_window's ends (on duals: engine/measures/lyapunov_lanes.hpp).
void SpecReader::check_adaptive_measures() const {
  if (!find_method(spec_.method)->adaptive) return;
  auto refuse = [&](std::string_view what, std::string_view why) {
    fail(section("integrator").get("method"),
         fmt::format("method {} does not support {} yet: {}", toml_string(spec_.method), what,
                     why));
  };
  for (const GridAxis& axis : spec_.axes)
    if (axis.is_step_size)
      refuse("a grid over h", "h is only its first step; vary integrator.rtol in runs of their own");
}

void SpecReader::read_method(const toml::table& t) {
  const toml::node* node = t.get("method");
  spec_.method =
      node != nullptr ? string(*node, "integrator.method") : std::string(kDefaultMethod);
  const MethodInfo* method = find_method(spec_.method);
  const Names methods = names_of(method_catalog());
  if (method == nullptr)
    fail(node, fmt::format("unknown method {}{}; valid methods: {}", toml_string(spec_.method),
                           did_you_mean(spec_.method, methods, ""), fmt::join(methods, ", ")));
  const Names missing = missing_split_parts(*method, scene_->split_parts);
  if (!missing.empty() && spec_.custom)
    fail(node, fmt::format("method {} needs K = sum of p_i^2/2 + V(q, t) + c(t)*z (or "
                           "c(t)*z^2), and scene.K does not split so; methods that work here: {}",
                           toml_string(spec_.method), fmt::join(usable_methods(), ", ")));
  if (!missing.empty())
    fail(node,
         fmt::format("method {} needs the exact sub-flow(s) {} that scene '{}' does not "
                     "offer (it offers: {}); methods that work here: {}",
                     toml_string(spec_.method), fmt::join(missing, ", "), scene_->name,
                     fmt::join(scene_->split_parts, ", "), fmt::join(usable_methods(), ", ")));
}

Names SpecReader::usable_methods() const {
  Names usable;
  for (const MethodInfo& m : method_catalog())
    if (missing_split_parts(m, scene_->split_parts).empty()) usable.push_back(m.name);
  return usable;
}

std::string SpecReader::duration_name() const {
  return spec_.t_start == 0.0 ? "t_end" : "t_end - t_start";
}

std::int64_t SpecReader::whole_steps(const toml::node* at) const {
  const double h = spec_.h, t0 = spec_.t_start, duration = spec_.t_end - t0;
  const double ratio = duration / h;
  const std::string span = duration_name();
  if (duration < h)
    fail(at, fmt::format("integrator.{} = {} is shorter than one step h = {}", span, duration, h));
  if (!(ratio <= kMaxSteps))
    fail(at, fmt::format("integrator.{} / h = {:.6g} steps: expected at most 2^53", span, ratio));
  const std::int64_t steps = std::llround(ratio);
  if (std::abs(static_cast<double>(steps) * h - duration) <= kStepTolerance * duration)
    return steps;
  const auto below = static_cast<std::int64_t>(std::floor(ratio));
  fail(at, fmt::format("integrator.{} = {} is not a whole number of steps of h = {} "
                       "({} / h = {:.12g}); nearest valid t_end: {:.15g} ({} steps) or "
                       "{:.15g} ({} steps)",
                       span, duration, h, span, ratio, t0 + static_cast<double>(below) * h,
                       below, t0 + static_cast<double>(below + 1) * h, below + 1));
}

}  // namespace cs::spec
