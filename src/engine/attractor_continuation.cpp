#include "engine/attractor_continuation.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <tuple>

#include "engine/attractor_search.hpp"
#include "engine/measures/observe_plan.hpp"
#include "engine/recurrence/default_range.hpp"

namespace cs {
namespace {

// Where a branch was last seen, and before that (for its extrapolation).
struct BranchTrack {
  Attractor last;
  double last_value = 0.0;
  bool has_previous = false;
  Attractor previous;
  double previous_value = 0.0;
};

// The branch's point linearly extrapolated to `value` from its last two sightings; empty when
// it has one (or is a set of cells, which does not move as a point).
std::vector<double> extrapolated(const BranchTrack& b, double value,
                                 const std::vector<double>& angle_period) {
  if (!b.has_previous || b.last.period == 0 || b.last_value == b.previous_value) return {};
  const double s = (value - b.last_value) / (b.last_value - b.previous_value);
  std::vector<double> x = b.last.point;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double period = k < angle_period.size() ? angle_period[k] : 0.0;
    x[k] += s * phase_difference(b.last.point[k], b.previous.point[k], period);
  }
  return x;
}

double cell_set_distance(const RecurrenceSearch& r, const std::vector<std::uint64_t>& a,
                         const std::vector<std::uint64_t>& b) {
  std::vector<std::vector<double>> centres;
  for (std::uint64_t key : b) centres.push_back(cell_centre(r, key));
  double nearest = INFINITY;
  for (std::uint64_t key : a) {
    const std::vector<double> x = cell_centre(r, key);
    for (const auto& y : centres) {
      double d = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k)
        d = std::fmax(d, std::fabs(phase_difference(x[k], y[k], r.angle_period[k])));
      nearest = std::fmin(nearest, d);
    }
  }
  return nearest;
}

// The smallest distance between two attractors of one table (infinite with fewer than two).
double separation(const std::vector<Attractor>& table, const AttractorDistance& distance) {
  double s = INFINITY;
  for (std::size_t i = 0; i < table.size(); ++i)
    for (std::size_t j = i + 1; j < table.size(); ++j)
      s = std::fmin(s, distance(table[i], table[j]));
  return s;
}

}  // namespace

ContinuationAxis continuation_axis(const RunPlan& plan) {
  const RunSpec& spec = plan.spec;
  ContinuationAxis axis;
  axis.first_point = plan.point_offset;
  axis.points_per_value = spec.grid_points();
  if (spec.axes.size() < 2 || !spec.axes.front().is_parameter) return axis;
  axis.along_parameter = true;
  axis.values = std::ssize(spec.axes.front().values);
  axis.points_per_value = spec.grid_points() / axis.values;
  return axis;
}

double match_threshold(const RunPlan& plan) {
  if (plan.spec.measures.basin && plan.spec.measures.basin->continuation_threshold)
    return *plan.spec.measures.basin->continuation_threshold;
  double widest = 0.0;
  const int n = 2 * plan.scene.dof;
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double period = plan.attractors.angle_period[i];
    if (plan.recurrence.enabled) {
      widest = std::max(widest, plan.recurrence.upper[i] - plan.recurrence.lower[i]);
    } else if (period > 0.0) {
      widest = std::max(widest, period);
    } else {
      const auto range = default_range(plan.spec, plan.scene.variables[i].name);
      widest = std::max(widest, range[1] - range[0]);
    }
  }
  return widest / 10.0;
}

double attractor_distance(const RunPlan& plan, const Attractor& a, const Attractor& b) {
  // A stop's exits (observe_plan.hpp) are the same exit where their channel is, whatever the value.
  if (a.period == kExitPeriod || b.period == kExitPeriod)
    return a.period == b.period && a.point[0] == b.point[0] ? 0.0 : INFINITY;
  if (a.period == 0 && b.period == 0 && !a.cells.empty() && !b.cells.empty())
    return cell_set_distance(plan.recurrence, a.cells, b.cells);
  double d = 0.0;
  for (std::size_t k = 0; k < a.point.size(); ++k)
    d = std::fmax(d, std::fabs(phase_difference(a.point[k], b.point[k],
                                                plan.attractors.angle_period[k])));
  return d;
}

Continuation continue_attractors(std::vector<std::vector<Attractor>> tables,
                                 const std::vector<double>& values,
                                 const AttractorDistance& distance, double threshold,
                                 const std::vector<double>& angle_period) {
  Continuation c;
  std::vector<BranchTrack> tracks;
  for (std::size_t v = 0; v < tables.size(); ++v) {
    std::vector<Attractor>& table = tables[v];
    // A move is a move only if it is small beside the distance between distinct attractors, here
    // and at the value before: else the parameter's steps are too coarse to tell (the pendulum's
    // maxima ±3π at γ = 0, where lanes that start on them stay, are not its minima ±2π at γ > 0).
    double within = std::fmin(threshold, kSeparationShare * separation(table, distance));
    if (v > 0) within = std::fmin(within, kSeparationShare * separation(c.along[v - 1], distance));
    // Every admissible pair, nearest first; ties by branch, then by the table's order.
    std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
    for (std::size_t b = 0; b < tracks.size(); ++b) {
      const std::vector<double> ahead = extrapolated(tracks[b], values[v], angle_period);
      Attractor predicted = tracks[b].last;
      predicted.point = ahead;
      for (std::size_t j = 0; j < table.size(); ++j) {
        if (table[j].period != tracks[b].last.period) continue;
        // Ranked by the distance to the extrapolation where there is one (two branches that
        // cross are told apart by where they are going), admitted by the nearer of the two
        // (a branch that stops moving is not lost).
        const double from_last = distance(tracks[b].last, table[j]);
        const double ahead_d = ahead.empty() ? from_last : distance(predicted, table[j]);
        if (std::fmin(from_last, ahead_d) <= within) pairs.emplace_back(ahead_d, b, j);
      }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<int> branch_of(table.size(), -1);
    std::vector<bool> taken(tracks.size(), false);
    for (const auto& [d, b, j] : pairs) {
      if (taken[b] || branch_of[j] >= 0) continue;
      taken[b] = true;
      branch_of[j] = static_cast<int>(b);
    }
    for (std::size_t j = 0; j < table.size(); ++j) {
      if (branch_of[j] < 0) {  // a new branch: appeared here
        branch_of[j] = static_cast<int>(tracks.size());
        tracks.push_back({table[j], values[v], false, {}, 0.0});
        c.branches.push_back(table[j]);
        c.branches.back().label = static_cast<int>(c.branches.size());
      } else {
        BranchTrack& t = tracks[static_cast<std::size_t>(branch_of[j])];
        t.previous = std::move(t.last), t.previous_value = t.last_value, t.has_previous = true;
        t.last = table[j], t.last_value = values[v];
      }
      table[j].label = branch_of[j] + 1;
    }
    c.along.push_back(std::move(table));
  }
  return c;
}

}  // namespace cs
