#include "engine/attractor_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <fmt/format.h>

#include "engine/attractor_analysis.hpp"
#include "engine/attractor_continuation.hpp"
#include "engine/attractor_search.hpp"
#include "engine/label_rule.hpp"
#include "engine/recurrence/lane_records.hpp"
#include "engine/recurrence/recurrence_table.hpp"
#include "engine/settlement_records.hpp"

namespace cs {
namespace {

int phase_space(const RunPlan& plan) { return 2 * plan.scene.dof; }

double distance(const RunPlan& plan, const double* x, const double* y) {
  double d = 0.0;
  for (int k = 0; k < phase_space(plan); ++k)
    d = std::fmax(d, std::fabs(phase_difference(
                         x[k], y[k], plan.attractors.angle_period[static_cast<std::size_t>(k)])));
  return d;
}

double link_distance(const RunPlan& plan) { return kLinkTolerances * plan.attractors.tolerance; }

// Whether a point of that period is `a`: within the link distance, or for a stop's exit
// (kExitPeriod, point (channel, 0, …)) the same channel.
bool same_attractor(const RunPlan& plan, const Attractor& a, int period, const double* point) {
  if (a.period != period) return false;
  if (period == kExitPeriod) return a.point[0] == point[0];
  return distance(plan, a.point.data(), point) <= link_distance(plan);
}

// A lane's or candidate's attractor: its point and period.
struct Sighting {
  const double* point;
  int period;
  std::int64_t source;  // grid index of a lane on it
};

// Adds a sighting to `table` unless one of the same period lies within the link distance:
// first come, first kept, so the order of sightings decides the representatives.
void add_sighting(const RunPlan& plan, const Sighting& s, std::vector<Attractor>& table) {
  for (const Attractor& a : table)
    if (same_attractor(plan, a, s.period, s.point)) return;
  table.push_back({0, s.period, std::vector<double>(s.point, s.point + phase_space(plan)), {},
                   s.source, std::nullopt});
}

// A candidate's values: {block begin, value, period, point..}, then the recurrence record where
// the recurrence mapper runs (NaN for the others).
std::size_t record_width(const RunPlan& plan) {
  return kCandidateHead + static_cast<std::size_t>(phase_space(plan)) +
         (plan.map.basin_cells >= 0 ? RecurrenceSearch::kRecordWidth : 0);
}

bool by_recurrence(const RunPlan& plan, const double* point) {
  return plan.map.basin_cells >= 0 && point[phase_space(plan)] == 0.0;
}

// The candidates of the block's lanes [from, to) (offsets into the block), all at `value` of
// the continuation axis, appended to `records`.
void add_point_candidates(const RunPlan& plan, const BlockResults& block, std::int64_t from,
                          std::int64_t to, std::int64_t value, std::vector<double>& records) {
  const int n = phase_space(plan);
  std::vector<Attractor> found;
  // A record already in `found`, or linked to one. Records are distinct (settlement_records.hpp):
  // a lane with the same record as the last one looked at needs no search.
  const double* previous = nullptr;
  for (std::int64_t i = from; i < to; ++i) {
    const double* point = settlement_of(plan, block, static_cast<std::size_t>(i));
    if (point == nullptr) continue;
    if (by_recurrence(plan, point)) continue;  // told apart by their cells, below
    if (point == previous) continue;
    add_sighting(plan, {point, static_cast<int>(point[n]), block.range.begin + i}, found);
    previous = point;
  }
  const std::size_t width = record_width(plan);
  for (const Attractor& a : found) {
    records.push_back(static_cast<double>(a.source));
    records.push_back(static_cast<double>(value));
    records.push_back(a.period);
    records.insert(records.end(), a.point.begin(), a.point.end());
    records.resize(records.size() + width - kCandidateHead - a.point.size(), std::nan(""));
  }
}

// Each fixed point of `attractors` its linearisation, evaluated once; the unstable ones moved to
// `refused` (label 0), in their order. After the merge, so that the lanes that settled on one
// are still told from those of its neighbours (label_block: nearest of both), and before the
// sort and the labels, which then are the others' alone. Every rank merges the same candidates
// in the same order and evaluates the same formula at the same points: the same bits.
void refuse_unstable(const RunPlan& plan, FixedPointExponentFn fixed,
                     std::vector<Attractor>& attractors, std::vector<Attractor>& refused) {
  if (fixed == nullptr) return;
  std::vector<Attractor> kept;
  for (Attractor& a : attractors) {
    if (a.period != kExitPeriod) a.linearisation = linearisation_of(plan, a, fixed);
    if (a.linearisation && unstable_fixed_point(plan, a, *a.linearisation)) {
      a.label = 0;
      refused.push_back(std::move(a));
    } else {
      kept.push_back(std::move(a));
    }
  }
  attractors = std::move(kept);
}

// One value's table (a whole map's without a continuation axis) from its candidates (offsets
// into `records`, in block order), sorted by (period, point), then the attractors found by
// recurrences; not labelled yet. Unstable fixed points go to `refused` (refuse_unstable).
std::vector<Attractor> value_table(const RunPlan& plan, const std::vector<double>& records,
                                   const std::vector<std::size_t>& order,
                                   FixedPointExponentFn fixed, std::vector<Attractor>& refused) {
  std::vector<Attractor> attractors;
  std::vector<std::size_t> by_cells;
  for (std::size_t r : order) {
    const double period = records[r + 2];
    if (plan.map.basin_cells >= 0 && period == 0.0) by_cells.push_back(r);
    else
      add_sighting(plan,
                   {&records[r + kCandidateHead], static_cast<int>(period),
                    static_cast<std::int64_t>(records[r])},
                   attractors);
  }
  refuse_unstable(plan, fixed, attractors, refused);
  // Coordinates within the link distance count as equal, so that the order (and the labels) do
  // not hang on the last digits of where lanes happened to settle: the magnetic pendulum's
  // magnets at (−1/2, ±√3/2) share q1 up to rounding.
  const double link = link_distance(plan);
  const std::size_t n = static_cast<std::size_t>(phase_space(plan));
  std::sort(attractors.begin(), attractors.end(), [&](const Attractor& a, const Attractor& b) {
    if (a.period != b.period) return a.period < b.period;
    for (std::size_t k = 0; k < n; ++k)
      if (std::fabs(a.point[k] - b.point[k]) > link) return a.point[k] < b.point[k];
    return false;
  });
  // Then the attractors found by recurrences, in order of their smallest cell.
  if (plan.map.basin_cells >= 0) add_recurrence_attractors(plan, records, by_cells, attractors);
  return attractors;
}

}  // namespace

std::vector<double> block_candidates(const RunPlan& plan, const BlockResults& block) {
  const ContinuationAxis axis = continuation_axis(plan);
  std::vector<double> records;
  const std::int64_t begin = block.range.begin, end = block.range.end;
  for (std::int64_t from = begin; from < end;) {  // one run of lanes per value of the axis
    const std::int64_t value = axis.value_of(from);
    const std::int64_t to = std::min(end, axis.first_point + (value + 1) * axis.points_per_value);
    add_point_candidates(plan, block, from - begin, to - begin, value, records);
    from = to;
  }
  if (plan.map.basin_cells >= 0)
    add_recurrence_candidates(plan, block, records, record_width(plan), axis);
  return records;
}

AttractorTable merge_candidates(const RunPlan& plan, const std::vector<double>& records,
                                FixedPointExponentFn fixed) {
  const std::size_t width = record_width(plan);
  const ContinuationAxis axis = continuation_axis(plan);
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r + width <= records.size(); r += width) order.push_back(r);
  // Block order, and within a block the order its lanes found them in.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return records[a] < records[b]; });
  std::vector<std::vector<std::size_t>> by_value(static_cast<std::size_t>(axis.values));
  for (std::size_t r : order) by_value[static_cast<std::size_t>(records[r + 1])].push_back(r);
  AttractorTable table;
  // With a stop, exits are outcomes too (numbered first): the scene's own rule is for attractors.
  const LabelRule rule = plan.spec.measures.stop ? LabelRule{} : plan.scene.label_rule;
  const std::string& q1 = plan.scene.variables.front().name;
  std::vector<std::vector<Attractor>> refused(axis.along_parameter ? by_value.size() : 1);
  const auto keep_refused = [&] {  // only where some were: a table without stays as it was
    if (std::any_of(refused.begin(), refused.end(), [](const auto& r) { return !r.empty(); }))
      table.refused = std::move(refused);
  };
  if (!axis.along_parameter) {
    table.attractors = value_table(plan, records, by_value.front(), fixed, refused.front());
    table.labels = apply_label_rule(rule, q1, table.attractors);
    keep_refused();
    return table;
  }
  std::vector<std::vector<Attractor>> tables;
  for (std::size_t v = 0; v < by_value.size(); ++v)
    tables.push_back(value_table(plan, records, by_value[v], fixed, refused[v]));
  keep_refused();
  Continuation c = continue_attractors(
      std::move(tables), plan.spec.axes.front().values,
      [&](const Attractor& a, const Attractor& b) { return attractor_distance(plan, a, b); },
      match_threshold(plan), plan.attractors.angle_period);
  table.attractors = std::move(c.branches);
  table.along = std::move(c.along);
  table.labels = apply_label_rule(rule, q1, table.attractors, table.along);
  return table;
}

std::int64_t label_block(const RunPlan& plan, const std::vector<Attractor>& whole,
                         BlockResults& block, const std::vector<std::vector<Attractor>>& along,
                         const std::vector<std::vector<Attractor>>& refused) {
  const int n = phase_space(plan);
  const ContinuationAxis axis = continuation_axis(plan);
  auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  const double* previous = nullptr;  // the last lane labelled, its label, and whether refused
  double previous_label = 0.0;
  bool previous_refused = false;
  std::int64_t value = -1, refused_lanes = 0;
  static const std::vector<Attractor> none;
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    const double* point = settlement_of(plan, block, static_cast<std::size_t>(i));
    if (point == nullptr) continue;
    double& label = labels[static_cast<std::size_t>(i)];
    if (!along.empty() && axis.value_of(block.range.begin + i) != value) {
      value = axis.value_of(block.range.begin + i);
      previous = nullptr;  // another value, another table
    }
    const std::vector<Attractor>& table =
        along.empty() ? whole : along[static_cast<std::size_t>(value)];
    const std::vector<Attractor>& unstable =
        refused.empty() ? none : refused[along.empty() ? 0 : static_cast<std::size_t>(value)];
    if (by_recurrence(plan, point)) {
      label = recurrence_label(table, recurrence_record_of(plan, block, static_cast<std::size_t>(i)));
      continue;
    }
    if (point == previous) {
      label = previous_label;
      refused_lanes += previous_refused;
      continue;
    }
    double nearest = INFINITY;
    for (const Attractor& a : table) {
      if (a.period != static_cast<int>(point[n])) continue;
      if (a.period == kExitPeriod && a.point[0] != point[0]) continue;
      const double d = distance(plan, a.point.data(), point);
      if (d < nearest) nearest = d, label = a.label;
    }
    // The refused points were merged beside the others (refuse_unstable): a lane belongs to
    // the nearest of them all, as it would with the point in the table, and is undecided there.
    bool on_refused = false;
    for (const Attractor& a : unstable) {
      if (a.period != static_cast<int>(point[n])) continue;
      const double d = distance(plan, a.point.data(), point);
      if (d < nearest) nearest = d, label = 0.0, on_refused = true;
    }
    refused_lanes += on_refused;
    if (nearest == INFINITY) label = 0.0;  // never: the table holds every period met
    else previous = point, previous_label = label, previous_refused = on_refused;
  }
  return refused_lanes;
}

}  // namespace cs
