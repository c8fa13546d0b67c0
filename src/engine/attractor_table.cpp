#include "engine/attractor_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

#include <fmt/format.h>

#include "engine/attractor_search.hpp"

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

// A lane's or candidate's attractor: its point, period and (trap) label.
struct Sighting {
  const double* point;
  int period;
  int label;
};

// Adds a sighting to `table` unless one of the same period and label lies within the link
// distance: first come, first kept, so the order of sightings decides the representatives.
void add_sighting(const RunPlan& plan, const Sighting& s, std::vector<Attractor>& table) {
  for (const Attractor& a : table)
    if (a.period == s.period && a.label == s.label &&
        distance(plan, a.point.data(), s.point) <= link_distance(plan))
      return;
  table.push_back({s.label, s.period, std::vector<double>(s.point, s.point + phase_space(plan))});
}

const double* point_of(const RunPlan& plan, const BlockResults& block, std::int64_t i) {
  const int width = phase_space(plan) + 1;
  return block.columns[static_cast<std::size_t>(plan.map.basin_point)].data() + i * width;
}

// The double well's trap: the minimum (±a, 0) of the well a lane labelled ±1 fell into.
class WellMinima {
 public:
  explicit WellMinima(const RunPlan& plan)
      : plan_(plan),
        params_(static_cast<std::size_t>(plan.grid.parameter_count())),
        state_(static_cast<std::size_t>(plan.grid.variable_count())) {
    while (plan.scene.parameters[a_].name != "a") ++a_;  // the double well's well position
  }
  std::array<double, 2> operator()(std::int64_t k, double label) {
    plan_.grid.point(k, params_.data(), state_.data());
    return {label * params_[a_], 0.0};
  }

 private:
  const RunPlan& plan_;
  std::vector<double> params_, state_;
  std::size_t a_ = 0;
};

}  // namespace

std::vector<double> block_candidates(const RunPlan& plan, const BlockResults& block) {
  const int n = phase_space(plan);
  const auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  std::vector<Attractor> found;
  std::optional<WellMinima> well_minimum;
  if (plan.basin_mode == BasinMode::trap) well_minimum.emplace(plan);
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    const double label = labels[static_cast<std::size_t>(i)];
    if (label == 0.0) continue;
    if (well_minimum) {
      const auto minimum = (*well_minimum)(block.range.begin + i, label);
      add_sighting(plan, {minimum.data(), 1, static_cast<int>(label)}, found);
      continue;
    }
    const double* point = point_of(plan, block, i);
    add_sighting(plan, {point, static_cast<int>(point[n]), 0}, found);
  }
  std::vector<double> records;
  for (const Attractor& a : found) {
    records.push_back(static_cast<double>(block.range.begin));
    records.push_back(a.period);
    records.push_back(a.label);
    records.insert(records.end(), a.point.begin(), a.point.end());
  }
  return records;
}

std::vector<Attractor> merge_candidates(const RunPlan& plan, const std::vector<double>& records) {
  const std::size_t width = static_cast<std::size_t>(phase_space(plan)) + 3;
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r + width <= records.size(); r += width) order.push_back(r);
  // Block order, and within a block the order its lanes found them in.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return records[a] < records[b]; });
  std::vector<Attractor> table;
  for (std::size_t r : order)
    add_sighting(plan,
                 {&records[r + 3], static_cast<int>(records[r + 1]), static_cast<int>(records[r + 2])},
                 table);
  // Coordinates within the link distance count as equal, so that the order (and the labels) do
  // not hang on the last digits of where lanes happened to settle: the magnetic pendulum's
  // magnets at (−1/2, ±√3/2) share q1 up to rounding.
  const double link = link_distance(plan);
  const std::size_t n = static_cast<std::size_t>(phase_space(plan));
  std::sort(table.begin(), table.end(), [&](const Attractor& a, const Attractor& b) {
    if (a.label != b.label) return a.label < b.label;
    if (a.period != b.period) return a.period < b.period;
    for (std::size_t k = 0; k < n; ++k)
      if (std::fabs(a.point[k] - b.point[k]) > link) return a.point[k] < b.point[k];
    return false;
  });
  if (plan.basin_mode != BasinMode::trap) {
    for (std::size_t k = 0; k < table.size(); ++k) table[k].label = static_cast<int>(k) + 1;
  }
  return table;
}

void label_block(const RunPlan& plan, const std::vector<Attractor>& table, BlockResults& block) {
  if (plan.basin_mode == BasinMode::trap) return;  // the trap's labels are final
  const int n = phase_space(plan);
  auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  for (std::int64_t i = 0; i < block.range.end - block.range.begin; ++i) {
    double& label = labels[static_cast<std::size_t>(i)];
    if (label == 0.0) continue;
    const double* point = point_of(plan, block, i);
    double nearest = INFINITY;
    for (const Attractor& a : table) {
      if (a.period != static_cast<int>(point[n])) continue;
      const double d = distance(plan, a.point.data(), point);
      if (d < nearest) nearest = d, label = a.label;
    }
  }
}

}  // namespace cs
