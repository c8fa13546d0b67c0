#include "engine/recurrence/recurrence_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>

#include "engine/recurrence/attractor_cells.hpp"
#include "engine/recurrence/lane_records.hpp"
#include "engine/settlement_records.hpp"

namespace cs {
namespace {

constexpr std::size_t kRecord = RecurrenceSearch::kRecordWidth;

// The keys a record names: its representative and its sketch.
std::vector<std::uint64_t> keys_of(const double* record) {
  std::vector<std::uint64_t> keys{static_cast<std::uint64_t>(record[0])};
  for (std::size_t k = 2; k < kRecord; ++k)
    if (!std::isnan(record[k])) keys.push_back(static_cast<std::uint64_t>(record[k]));
  return keys;
}

}  // namespace

void add_recurrence_candidates(const RunPlan& plan, const BlockResults& block,
                               std::vector<double>& records, std::size_t width,
                               const ContinuationAxis& axis) {
  const auto n = static_cast<std::size_t>(2 * plan.scene.dof);
  const auto lanes = static_cast<std::size_t>(block.range.end - block.range.begin);
  // Records compared by value (and value of the continuation axis): the same cells, one candidate.
  std::set<std::vector<double>> seen;
  for (std::size_t i = 0; i < lanes; ++i) {
    const double* point = settlement_of(plan, block, i);
    if (point == nullptr || point[n] != 0.0) continue;
    const double* record = recurrence_record_of(plan, block, i);
    const auto value =
        static_cast<double>(axis.value_of(block.range.begin + static_cast<std::int64_t>(i)));
    std::vector<double> r{value};
    r.insert(r.end(), record, record + kRecord);
    for (double& v : r)
      if (std::isnan(v)) v = -1.0;  // NaN never equals itself: a set would keep every copy
    if (!seen.insert(r).second) continue;
    records.push_back(static_cast<double>(block.range.begin + static_cast<std::int64_t>(i)));
    records.push_back(value);
    records.push_back(0.0);
    records.insert(records.end(), point, point + n);
    records.insert(records.end(), record, record + kRecord);
    records.resize(records.size() + (width - (kCandidateHead + n + kRecord)), std::nan(""));
  }
}

void add_recurrence_attractors(const RunPlan& plan, const std::vector<double>& records,
                               const std::vector<std::size_t>& offsets,
                               std::vector<Attractor>& table) {
  const RecurrenceSearch& r = plan.recurrence;
  std::vector<bool> wraps;
  for (double period : r.angle_period) wraps.push_back(period > 0.0);
  AttractorCells cells(r.cells, wraps);
  const std::size_t record_at = kCandidateHead + static_cast<std::size_t>(2 * plan.scene.dof);
  for (std::size_t offset : offsets) cells.add(keys_of(&records[offset + record_at]));
  for (auto& keys : cells.components()) {
    Attractor a;
    a.period = 0;
    a.point = cell_centre(r, keys.front());
    a.cells = std::move(keys);
    // A lane on it: the first in grid order whose representative cell is one of its cells.
    for (std::size_t offset : offsets)
      if (std::binary_search(a.cells.begin(), a.cells.end(),
                             static_cast<std::uint64_t>(records[offset + record_at])) &&
          (a.source < 0 || records[offset] < static_cast<double>(a.source)))
        a.source = static_cast<std::int64_t>(records[offset]);
    table.push_back(std::move(a));
  }
}

int recurrence_label(const std::vector<Attractor>& table, const double* record) {
  const auto key = static_cast<std::uint64_t>(record[0]);
  for (const Attractor& a : table)
    if (a.period == 0 && std::binary_search(a.cells.begin(), a.cells.end(), key)) return a.label;
  return 0;
}

}  // namespace cs
