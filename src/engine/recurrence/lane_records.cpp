#include "engine/recurrence/lane_records.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "engine/words_hash.hpp"

namespace cs {
namespace {

constexpr std::size_t kRecord = RecurrenceSearch::kRecordWidth;
// The bits of a settled lane's provisional value, record and reason.
using Key = std::array<std::uint64_t, kRecord + 2>;

bool compacted(const RunPlan& plan, const BlockResults& block) {
  return plan.map.basin_cells >= 0 && block.records_compacted;
}

void count(double why, std::int64_t* counts) {
  if (why >= 0.0 && why < kUndecidedReasons) ++counts[static_cast<int>(why)];
}

// Whether a settled lane needs an entry: not one settled by the fixed-point mappers (no record,
// decided), whose provisional value keeps naming its settlement.
bool needs_entry(const double* record, double why) {
  for (std::size_t k = 0; k < kRecord; ++k)
    if (!std::isnan(record[k])) return true;
  return why != static_cast<double>(UndecidedReason::decided);
}

// A compacted block's entries and settlement records: provisional values up to `settlements`
// name a settlement alone, those above it an entry.
struct Layout {
  std::size_t settlements, entries;
};

Layout layout_of(const RunPlan& plan, const BlockResults& block) {
  const auto width = static_cast<std::size_t>(2 * plan.scene.dof + 1);
  const std::size_t entries =
      block.columns[static_cast<std::size_t>(plan.map.basin_cells)].size() / kRecord;
  return {block.columns[static_cast<std::size_t>(plan.map.basin_records)].size() / width - entries,
          entries};
}

// The entry (0-based) of a settled lane's provisional value, or `entries` for none.
std::size_t entry_of(double provisional, const Layout& layout) {
  if (!(provisional >= 1.0) ||
      provisional > static_cast<double>(layout.settlements + layout.entries))
    throw std::logic_error(
        "a lane's recurrence entry is missing from its block");  // never, short of a bug
  const auto number = static_cast<std::size_t>(provisional);
  return number <= layout.settlements ? layout.entries : number - layout.settlements - 1;
}

// The bits of lane i's provisional value, record and reason.
Key key_of(const std::vector<double>& basin, const std::vector<double>& cells,
           const std::vector<double>& reasons, std::size_t i) {
  Key key;
  key[0] = std::bit_cast<std::uint64_t>(basin[i]);
  for (std::size_t k = 0; k < kRecord; ++k)
    key[1 + k] = std::bit_cast<std::uint64_t>(cells[i * kRecord + k]);
  key[kRecord + 1] = std::bit_cast<std::uint64_t>(reasons[i]);
  return key;
}

// Whether the block's distinct entries (a record, a settlement's copy and a reason each) cost
// less than its per-point records and reasons. A strange attractor's lanes mostly differ in their
// sketches, so a block may keep nearly one entry a lane: it then keeps the per-point layout, and
// the memory check (parallel/sweep.cpp) can count that layout as the most a block holds.
bool entries_pay(const std::vector<double>& basin, const std::vector<double>& cells,
                 const std::vector<double>& reasons, std::size_t width) {
  const std::size_t budget = basin.size() * (kRecord + 1) / (kRecord + width + 1);
  std::unordered_map<Key, char, WordsHash> seen;
  for (std::size_t i = 0; i < basin.size(); ++i) {
    if (basin[i] == 0.0 || !needs_entry(&cells[i * kRecord], reasons[i])) continue;
    seen.try_emplace(key_of(basin, cells, reasons, i), 0);
    if (seen.size() > budget) return false;
  }
  return true;
}

}  // namespace

void compact_recurrence_columns(const RunPlan& plan, BlockResults& block) {
  if (plan.map.basin_cells < 0 || block.basin_compacted || block.records_compacted) return;
  auto& basin = block.columns[static_cast<std::size_t>(plan.map.basin)];
  auto& settlements = block.columns[static_cast<std::size_t>(plan.map.basin_records)];
  auto& cells = block.columns[static_cast<std::size_t>(plan.map.basin_cells)];
  auto& reasons = block.columns[static_cast<std::size_t>(plan.map.undecided_reason)];
  const auto width = static_cast<std::size_t>(2 * plan.scene.dof + 1);
  if (!entries_pay(basin, cells, reasons, width)) return;
  const std::size_t count_of_settlements = settlements.size() / width;
  std::vector<double> copies, records, why(kUndecidedReasons, 0.0);
  std::int64_t unsettled[kUndecidedReasons] = {};
  std::unordered_map<Key, double, WordsHash> numbers;
  Key last{};
  double last_number = 0.0;
  for (std::size_t i = 0; i < basin.size(); ++i) {
    const double* record = &cells[i * kRecord];
    if (basin[i] == 0.0) {
      count(reasons[i], unsettled);
      continue;
    }
    if (!needs_entry(record, reasons[i])) continue;
    const Key key = key_of(basin, cells, reasons, i);
    if (last_number > 0.0 && key == last) {  // neighbours mostly share their entry
      basin[i] = last_number;
      continue;
    }
    const auto [it, added] =
        numbers.try_emplace(key, static_cast<double>(count_of_settlements + numbers.size() + 1));
    if (added) {
      const auto number = static_cast<std::size_t>(basin[i]);
      if (!(basin[i] >= 1.0) || number > count_of_settlements)  // never, short of a bug
        throw std::logic_error("a lane's basin record is missing from its block");
      const double* point = &settlements[(number - 1) * width];
      copies.insert(copies.end(), point, point + width);
      records.insert(records.end(), record, record + kRecord);
      why.push_back(reasons[i]);
    }
    last = key;
    basin[i] = last_number = it->second;
  }
  for (int r = 0; r < kUndecidedReasons; ++r)
    why[static_cast<std::size_t>(r)] = static_cast<double>(unsettled[r]);
  settlements.resize(count_of_settlements * width);
  settlements.insert(settlements.end(), copies.begin(), copies.end());
  cells = std::move(records);
  reasons = std::move(why);
  settlements.shrink_to_fit(), cells.shrink_to_fit(), reasons.shrink_to_fit();
  block.records_compacted = true;
}

const double* recurrence_record_of(const RunPlan& plan, const BlockResults& block,
                                   std::size_t lane) {
  static const std::vector<double> none(kRecord, std::nan(""));
  const auto& cells = block.columns[static_cast<std::size_t>(plan.map.basin_cells)];
  if (!compacted(plan, block)) return &cells[lane * kRecord];
  const Layout layout = layout_of(plan, block);
  const std::size_t entry =
      entry_of(block.columns[static_cast<std::size_t>(plan.map.basin)][lane], layout);
  return entry == layout.entries ? none.data() : &cells[entry * kRecord];
}

void count_undecided(const RunPlan& plan, const BlockResults& block,
                     const std::vector<double>& provisional, std::int64_t* counts) {
  if (plan.map.undecided_reason < 0) return;
  const auto& labels = block.columns[static_cast<std::size_t>(plan.map.basin)];
  const auto& reasons = block.columns[static_cast<std::size_t>(plan.map.undecided_reason)];
  if (!compacted(plan, block)) {
    for (std::size_t i = 0; i < labels.size(); ++i)
      if (labels[i] == 0.0) count(reasons[i], counts);
    return;
  }
  for (int r = 0; r < kUndecidedReasons; ++r)
    counts[r] += static_cast<std::int64_t>(reasons[static_cast<std::size_t>(r)]);
  const Layout layout = layout_of(plan, block);
  for (std::size_t i = 0; i < labels.size(); ++i) {  // settled, yet on no attractor of the table
    if (labels[i] != 0.0 || provisional[i] == 0.0) continue;
    const std::size_t entry = entry_of(provisional[i], layout);
    count(entry == layout.entries ? 0.0 : reasons[kUndecidedReasons + entry], counts);
  }
}

}  // namespace cs
