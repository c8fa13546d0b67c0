#include "engine/attractor_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <fmt/format.h>

#include "engine/attractor_search.hpp"
#include "engine/label_rule.hpp"
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
    if (a.period == s.period && distance(plan, a.point.data(), s.point) <= link_distance(plan))
      return;
  table.push_back(
      {0, s.period, std::vector<double>(s.point, s.point + phase_space(plan)), {}, s.source});
}

// A candidate's values: {block begin, period, point..}, then the recurrence record where the
// recurrence mapper runs (NaN for the others).
std::size_t record_width(const RunPlan& plan) {
  return 2 + static_cast<std::size_t>(phase_space(plan)) +
         (plan.map.basin_cells >= 0 ? RecurrenceSearch::kRecordWidth : 0);
}

bool by_recurrence(const RunPlan& plan, const double* point) {
  return plan.map.basin_cells >= 0 && point[phase_space(plan)] == 0.0;
}

}  // namespace

std::vector<double> block_candidates(const RunPlan& plan, const BlockResults& block) {
  const int n = phase_space(plan);
  std::vector<Attractor> found;
  // A record already in `found`, or linked to one. Records are distinct (settlement_records.hpp):
  // a lane with the same record as the last one looked at needs no search.
  const double* previous = nullptr;
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    const double* point = settlement_of(plan, block, static_cast<std::size_t>(i));
    if (point == nullptr) continue;
    if (by_recurrence(plan, point)) continue;  // told apart by their cells, below
    if (point == previous) continue;
    add_sighting(plan, {point, static_cast<int>(point[n]), block.range.begin + i}, found);
    previous = point;
  }
  const std::size_t width = record_width(plan);
  std::vector<double> records;
  for (const Attractor& a : found) {
    records.push_back(static_cast<double>(a.source));
    records.push_back(a.period);
    records.insert(records.end(), a.point.begin(), a.point.end());
    records.resize(records.size() + width - 2 - a.point.size(), std::nan(""));
  }
  if (plan.map.basin_cells >= 0) add_recurrence_candidates(plan, block, records, width);
  return records;
}

AttractorTable merge_candidates(const RunPlan& plan, const std::vector<double>& records) {
  const std::size_t width = record_width(plan);
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r + width <= records.size(); r += width) order.push_back(r);
  // Block order, and within a block the order its lanes found them in.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return records[a] < records[b]; });
  AttractorTable table;
  std::vector<Attractor>& attractors = table.attractors;
  std::vector<std::size_t> by_cells;
  for (std::size_t r : order) {
    if (plan.map.basin_cells >= 0 && records[r + 1] == 0.0) by_cells.push_back(r);
    else
      add_sighting(plan,
                   {&records[r + 2], static_cast<int>(records[r + 1]),
                    static_cast<std::int64_t>(records[r])},
                   attractors);
  }
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
  table.labels = apply_label_rule(plan.scene.label_rule, plan.scene.variables.front().name, attractors);
  return table;
}

void label_block(const RunPlan& plan, const std::vector<Attractor>& table, BlockResults& block) {
  const int n = phase_space(plan);
  auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  const double* previous = nullptr;  // the last lane's record, and its label
  double previous_label = 0.0;
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    const double* point = settlement_of(plan, block, static_cast<std::size_t>(i));
    if (point == nullptr) continue;
    double& label = labels[static_cast<std::size_t>(i)];
    if (by_recurrence(plan, point)) {
      const auto& cells = block.columns[static_cast<std::size_t>(plan.map.basin_cells)];
      label = recurrence_label(table, &cells[static_cast<std::size_t>(i) * RecurrenceSearch::kRecordWidth]);
      continue;
    }
    if (point == previous) {
      label = previous_label;
      continue;
    }
    double nearest = INFINITY;
    for (const Attractor& a : table) {
      if (a.period != static_cast<int>(point[n])) continue;
      const double d = distance(plan, a.point.data(), point);
      if (d < nearest) nearest = d, label = a.label;
    }
    if (nearest == INFINITY) label = 0.0;  // never: the table holds every period met
    else previous = point, previous_label = label;
  }
}

}  // namespace cs
