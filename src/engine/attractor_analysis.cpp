#include "engine/attractor_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/attractor_table.hpp"
#include "engine/measures/observe_plan.hpp"
#include "engine/run_plan.hpp"
#include "engine/scene_form.hpp"

namespace cs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool stroboscopic(const RunPlan& plan) { return plan.spec.measures.basin->period.has_value(); }

// A fixed point of an autonomous scene, as the energy trap or the anchor test found it.
bool table_fixed_point(const RunPlan& plan, const Attractor& a) {
  return !stroboscopic(plan) && a.period == 1;
}

// Is the Jacobian at the table's point the fixed point's linearisation? The table holds q and p
// alone, and the Jacobian is taken at the source lane's initial z and at t_start. Where z feeds
// back, the fixed point has a z* of its own (K(q*, p*, z*) = 0: z' = K − p·K_p), which the lane
// reached and the table does not hold (K = p²/2 + q²/2 + c − γz²: −γ·z0 instead of −γ√(c/γ));
// where K reads t, the linearisation at t_start is not the one the lanes settle under. There
// the orbit describes the point, as any other attractor.
bool exact_at_fixed_points(const RunPlan& plan) {
  return !plan.scene.z_feeds_back && !reads_time(plan.spec, plan.scene);
}

// The state at the table's point: q and p from it, z and the rest from the request (the
// source lane's).
std::vector<double> at_point(const Attractor& a, const OrbitRequest& request) {
  std::vector<double> state = request.state;
  std::copy(a.point.begin(), a.point.end(), state.begin());
  return state;
}

// The exact λ₁ of the table's fixed point `a` from its linearisation, NaN where there is none to
// take: not such a fixed point, no `fixed`, or `fixed` says it does not apply there (its
// Jacobian undefined at the point, or the field not vanishing to within the table's tolerance:
// fixed_point_exponent.cpp).
double exact_exponent(const RunPlan& plan, const Attractor& a, const FixedPointLinearisation& j) {
  if (!table_fixed_point(plan, a) || !exact_at_fixed_points(plan)) return kNaN;
  return j.lyapunov;
}

// Would a lane started at the table's fixed point break down at once? Where the Jacobian is not
// finite at the point, the orbit's formulas are the same expressions (0/0 in 2q³/√(q⁴) at q = 0,
// exactly where the energy trap puts the minimum): its first step is NaN, and so would be the
// attractor's λ₁. Such a lane starts where its source lane did instead, which the map integrated
// to the point without breaking down.
bool undefined_at_point(const RunPlan& plan, const Attractor& a, const FixedPointLinearisation& j) {
  return table_fixed_point(plan, a) && a.source >= 0 && j.undefined;
}

// What the table and the orbit say (classify adds the exact λ₁ of fixed points).
AttractorAnalysis described(const RunPlan& plan, const Attractor& a, const OrbitRequest& request,
                            const AttractorOrbit* orbit);

}  // namespace

FixedPointLinearisation linearisation_of(const RunPlan& plan, const Attractor& a,
                                         FixedPointExponentFn fixed) {
  if (a.linearisation) return *a.linearisation;
  // Where either question is asked of it: its exact λ₁ (exact_exponent), whether a lane from
  // it would break down (undefined_at_point). The request's z and parameters are the source
  // lane's, whichever lane the orbit starts from (orbit_request): the same state either way.
  if (fixed == nullptr || !table_fixed_point(plan, a) ||
      (!exact_at_fixed_points(plan) && a.source < 0))
    return {};
  const OrbitRequest request = orbit_request(plan, a);
  return fixed(plan, request.params, at_point(a, request), plan.attractors.tolerance);
}

bool unstable_fixed_point(const RunPlan& plan, const Attractor& a,
                          const FixedPointLinearisation& j) {
  const double exact = exact_exponent(plan, a, j);
  return exact > kUnstableMargin * j.norm;  // false for NaN
}

bool needs_orbits(const RunPlan& plan, const std::vector<Attractor>& table,
                  FixedPointExponentFn fixed) {
  for (const Attractor& a : table) {
    if (a.period == kExitPeriod) continue;  // nothing to integrate
    if (std::isnan(exact_exponent(plan, a, linearisation_of(plan, a, fixed)))) return true;
  }
  return false;
}

bool may_need_orbits(const RunPlan& plan) {
  return plan.map.basin >= 0 &&
         (stroboscopic(plan) || plan.recurrence.enabled || !exact_at_fixed_points(plan));
}

OrbitRequest orbit_request(const RunPlan& plan, const Attractor& a, bool from_source_lane) {
  const RunSpec& spec = plan.spec;
  const int n = 2 * plan.scene.dof;
  OrbitRequest r;
  r.params.resize(static_cast<std::size_t>(plan.grid.parameter_count()));
  r.state.resize(static_cast<std::size_t>(plan.grid.variable_count()));
  // The parameters and z of a lane that settled on it (the first in grid order of the block
  // that found it first). A point or cycle of the table is on the attractor to the tolerance:
  // q and p from it, half the run as a transient. An attractor found by recurrences has a
  // cell's centre as its point, which need not be on it nor even in its basin (a cotangent
  // lift's p = 0 is invariant, the cell's centre is off it): the lane's own start instead,
  // with the whole run as the transient, in which that lane reached it.
  plan.grid.point(a.source >= 0 ? a.source : 0, r.params.data(), r.state.data());
  const bool from_lane = (a.period == 0 || from_source_lane) && a.source >= 0;
  if (!from_lane)
    for (int k = 0; k < n; ++k)
      r.state[static_cast<std::size_t>(k)] = a.point[static_cast<std::size_t>(k)];
  if (!plan.lyapunov_seed.empty()) {  // the lyapunov measure's `vars`
    r.seed = plan.lyapunov_seed;
    r.log_norm0 = plan.lyapunov_log_norm0;
  } else {  // all of q and p; q alone where q closes on itself (found by the kernel)
    r.seed.assign(static_cast<std::size_t>(n) + 1, 0.0);
    for (int k = 0; k < n; ++k) r.seed[static_cast<std::size_t>(k)] = 1.0;
    r.log_norm0 = 0.5 * std::log(static_cast<double>(n));
    r.seed_q_where_closed = true;
  }
  r.h = spec.h;
  r.t_start = spec.t_start;
  r.tolerance = plan.attractors.tolerance;
  r.angle_period = plan.attractors.angle_period;
  r.stroboscopic = stroboscopic(plan);
  if (r.stroboscopic && plan.method.adaptive) {
    // An adaptive method's h need not divide the period: the orbit steps its formula at the
    // nearest h that does, over the run's whole periods.
    const double period = *spec.measures.basin->period;
    r.sample_steps = std::max<std::int64_t>(1, std::llround(period / spec.h));
    r.h = period / static_cast<double>(r.sample_steps);
    const std::int64_t periods = plan.attractors.strobe_last;
    r.transient_steps = (from_lane ? periods : periods / 2) * r.sample_steps;
    r.window_steps = r.samples * r.sample_steps;
  } else if (r.stroboscopic) {
    // One sample per forcing period, over K periods, after the transient rounded down to whole
    // periods (the point is on the section at t_start + k·period).
    r.sample_steps = std::llround(*spec.measures.basin->period / spec.h);
    r.transient_steps = (from_lane ? spec.steps : spec.steps / 2) / r.sample_steps * r.sample_steps;
    r.window_steps = r.samples * r.sample_steps;
  } else {
    // The window is the run's length t_end − t_start; K samples spread over it (over one
    // period instead where the orbit returns).
    r.transient_steps = from_lane ? spec.steps : spec.steps / 2;
    r.window_steps = spec.steps;
    r.sample_steps = std::max<std::int64_t>(1, spec.steps / r.samples);
  }
  return r;
}

AttractorAnalysis classify(const RunPlan& plan, const Attractor& a, const OrbitRequest& request,
                           const AttractorOrbit* orbit, const FixedPointLinearisation& j) {
  AttractorAnalysis out = described(plan, a, request, orbit);
  const double exact = exact_exponent(plan, a, j);
  if (!std::isnan(exact)) out.lyapunov = exact;
  return out;
}

namespace {

AttractorAnalysis described(const RunPlan& plan, const Attractor& a, const OrbitRequest& request,
                            const AttractorOrbit* orbit) {
  AttractorAnalysis out;
  out.lyapunov = out.time_period = kNaN;
  if (orbit == nullptr || !orbit->finite) {
    // Described by the table: the point repeated (a fixed point; a lane that diverged on its
    // way round cannot say more).
    for (int k = 0; k < request.samples; ++k)
      out.points.insert(out.points.end(), a.point.begin(), a.point.end());
    if (table_fixed_point(plan, a))
      out.kind = AttractorKind::fixed_point;
    else if (a.period >= 1) {
      out.kind = AttractorKind::periodic;
      out.time_period = a.period * *plan.spec.measures.basin->period;
    } else
      out.kind = AttractorKind::quasiperiodic;
    return out;
  }
  out.points = orbit->points;
  out.lyapunov = orbit->lyapunov;
  const double window = static_cast<double>(request.window_steps) * request.h;
  const bool chaotic = orbit->lyapunov > kChaosEfolds / window;
  if (request.stroboscopic) {
    const double period = *plan.spec.measures.basin->period;
    if (chaotic)
      out.kind = AttractorKind::chaotic;
    else if (a.period >= 1 || orbit->stroboscopic_return > 0) {
      out.kind = AttractorKind::periodic;
      out.time_period = (a.period >= 1 ? a.period : orbit->stroboscopic_return) * period;
    } else
      out.kind = AttractorKind::quasiperiodic;
  } else if (table_fixed_point(plan, a) || !orbit->moved) {
    out.kind = AttractorKind::fixed_point;
  } else if (chaotic) {
    out.kind = AttractorKind::chaotic;
  } else if (!std::isnan(orbit->return_time)) {
    out.kind = AttractorKind::periodic;
    out.time_period = orbit->return_time;
  } else {
    out.kind = AttractorKind::quasiperiodic;
  }
  return out;
}

}  // namespace

std::vector<AttractorAnalysis> analyse_attractors(const RunPlan& plan,
                                                  const std::vector<Attractor>& table,
                                                  OrbitFn orbit, FixedPointExponentFn fixed) {
  if (orbit == nullptr && needs_orbits(plan, table, fixed))
    throw std::logic_error("analyse_attractors: an orbit is needed but no kernel was built");
  std::vector<AttractorAnalysis> out(table.size());
  // Attractors are independent (each orbit reads its request alone): the threads share them,
  // and every result is the same bits whichever thread computed it.
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (table[i].period == kExitPeriod) {  // an exit, not an attractor: nothing to integrate
      out[i].kind = AttractorKind::exit;
      out[i].lyapunov = out[i].time_period = kNaN;
      out[i].points.assign(static_cast<std::size_t>(kAttractorSamples * 2 * plan.scene.dof), kNaN);
      continue;
    }
    OrbitRequest request = orbit_request(plan, table[i]);
    // One evaluation of the Jacobian for all three questions (none where the table holds it).
    const FixedPointLinearisation j = linearisation_of(plan, table[i], fixed);
    if (orbit == nullptr) {
      out[i] = classify(plan, table[i], request, nullptr, j);
      continue;
    }
    if (std::isnan(exact_exponent(plan, table[i], j)) && undefined_at_point(plan, table[i], j))
      request = orbit_request(plan, table[i], true);
    AttractorOrbit found;
    orbit(request, found);
    out[i] = classify(plan, table[i], request, &found, j);
  }
  return out;
}

}  // namespace cs
