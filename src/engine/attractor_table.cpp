#include "engine/attractor_table.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <fmt/format.h>

#include "engine/attractor_search.hpp"
#include "engine/label_rule.hpp"
#include "engine/recurrence/recurrence_table.hpp"

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
};

// Adds a sighting to `table` unless one of the same period lies within the link distance:
// first come, first kept, so the order of sightings decides the representatives.
void add_sighting(const RunPlan& plan, const Sighting& s, std::vector<Attractor>& table) {
  for (const Attractor& a : table)
    if (same_attractor(plan, a, s.period, s.point)) return;
  table.push_back({0, s.period, std::vector<double>(s.point, s.point + phase_space(plan)), {}});
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

const double* point_of(const RunPlan& plan, const BlockResults& block, std::int64_t i) {
  const int width = phase_space(plan) + 1;
  return block.columns[static_cast<std::size_t>(plan.map.basin_point)].data() + i * width;
}

// Whether two lanes' points and periods (phase_space + 1 values) are the same bits. Lanes next
// to each other mostly settle on the very same point (the energy trap's minima, as found once
// per run): then whatever was found for the one holds for the other, without a search.
// A loop, not memcmp: a call to the library's memcmp per lane cost more than it saved.
bool same_bits(const double* x, const double* y, int values) {
  for (int k = 0; k < values; ++k)
    if (std::bit_cast<std::uint64_t>(x[k]) != std::bit_cast<std::uint64_t>(y[k])) return false;
  return true;
}

}  // namespace

std::vector<double> block_candidates(const RunPlan& plan, const BlockResults& block) {
  const int n = phase_space(plan);
  const auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  std::vector<Attractor> found;
  const double* previous = nullptr;  // a sighting already in `found`, or linked to one
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    if (labels[static_cast<std::size_t>(i)] == 0.0) continue;
    const double* point = point_of(plan, block, i);
    if (by_recurrence(plan, point)) continue;  // told apart by their cells, below
    if (previous != nullptr && same_bits(point, previous, n + 1)) continue;
    add_sighting(plan, {point, static_cast<int>(point[n])}, found);
    previous = point;
  }
  const std::size_t width = record_width(plan);
  std::vector<double> records;
  for (const Attractor& a : found) {
    records.push_back(static_cast<double>(block.range.begin));
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
    else add_sighting(plan, {&records[r + 2], static_cast<int>(records[r + 1])}, attractors);
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
  // With a stop, exits are outcomes too (numbered first): the scene's own rule is for attractors.
  const LabelRule rule = plan.spec.measures.stop ? LabelRule{} : plan.scene.label_rule;
  table.labels = apply_label_rule(rule, plan.scene.variables.front().name, attractors);
  return table;
}

void label_block(const RunPlan& plan, const std::vector<Attractor>& table, BlockResults& block) {
  const int n = phase_space(plan);
  auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  const double* previous = nullptr;  // the last lane labelled, and its label
  double previous_label = 0.0;
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    double& label = labels[static_cast<std::size_t>(i)];
    if (label == 0.0) continue;
    const double* point = point_of(plan, block, i);
    if (by_recurrence(plan, point)) {
      const auto& cells = block.columns[static_cast<std::size_t>(plan.map.basin_cells)];
      label = recurrence_label(table, &cells[static_cast<std::size_t>(i) * RecurrenceSearch::kRecordWidth]);
      continue;
    }
    if (previous != nullptr && same_bits(point, previous, n + 1)) {
      label = previous_label;
      continue;
    }
    double nearest = INFINITY;
    for (const Attractor& a : table) {
      if (a.period != static_cast<int>(point[n])) continue;
      if (a.period == kExitPeriod && a.point[0] != point[0]) continue;
      const double d = distance(plan, a.point.data(), point);
      if (d < nearest) nearest = d, label = a.label;
    }
    if (nearest < INFINITY) previous = point, previous_label = label;
  }
}

}  // namespace cs
