// The recurrence mapper's per-point columns held compact once a block is saved
// (engine/recurrence/lane_records.hpp): a hand-built block's entries and counts, and a whole map
// whose table, labels and undecided counts are the same bits from compacted blocks as from the
// per-point columns.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/attractor_table.hpp"
#include "engine/basin_column.hpp"
#include "engine/recurrence/lane_records.hpp"
#include "engine/recurrence/recurrence_table.hpp"
#include "engine/run_plan.hpp"
#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

// The double well with the recurrence mapper on and no energy trap: lanes settle on the wells'
// cells by recurrences (two attractors of period 0) or on a well's point by the anchor test (two
// of period 1), and t_end leaves about a tenth of them recurred but not located.
const char* kSpec = R"(
  [scene]
  name = "double_well"
  gamma = 0.3
  [integrator]
  h = 0.05
  t_end = 75.0
  [grid]
  q_0 = { from = -2.5, to = 2.5, n = 24 }
  p_0 = { from = -2.5, to = 2.5, n = 24 }
  [measures]
  basin = { recurrence = true, exact_trap = false, cell_size = 0.25, recurrences = 10, locate = 20, box = { p = [-2.0, 2.0] } }
)";

std::unique_ptr<RunPlan> plan_of(const RunSpec& spec) {
  return std::make_unique<RunPlan>(spec, *find_scene(spec.scene), *find_method(spec.method));
}

std::vector<std::uint64_t> bits(const std::vector<double>& v) {
  std::vector<std::uint64_t> b;
  for (double x : v) b.push_back(std::bit_cast<std::uint64_t>(x));
  return b;
}

// The undecided lanes' reasons, counted as a run counts them once the attractor table has
// relabelled the block's lanes `labels` (the provisional ones being the block's `basin` now).
std::vector<std::int64_t> undecided_counts(const RunPlan& plan, BlockResults& block,
                                           const std::vector<double>& labels) {
  auto& basin = block.columns[static_cast<std::size_t>(plan.map.basin)];
  const std::vector<double> provisional = basin;
  basin = labels;
  std::int64_t counts[kUndecidedReasons] = {};
  count_undecided(plan, block, provisional, counts);
  return {counts, counts + kUndecidedReasons};
}

TEST(LaneRecords, HandBuiltBlockKeepsOneEntryPerDistinctRecordAndCountsReasons) {
  const RunSpec spec = parse_run_spec(kSpec, {"grid.q_0.n=2", "grid.p_0.n=3"}, "test spec");
  const auto plan = plan_of(spec);
  ASSERT_GE(plan->map.basin_cells, 0);
  BlockResults block({10, 16}, plan->columns);
  const auto at = [&](int c) -> std::vector<double>& {
    return block.columns[static_cast<std::size_t>(c)];
  };
  const double nan = std::nan("");
  // Two settlements: a fixed point (period 1) and a recurrence's cell centre (period 0).
  at(plan->map.basin_records) = {-1.0, 0.0, 1.0, 0.5, 0.5, 0.0};
  // Lanes: unsettled (no recurrence), the fixed point, recurrence record A, record B (same
  // settlement, another sketch), record A again, unsettled (left the box).
  at(plan->map.basin) = {0.0, 1.0, 2.0, 2.0, 2.0, 0.0};
  std::vector<double> none(RecurrenceSearch::kRecordWidth, nan), a = none, b = none;
  a[0] = 7, a[1] = 3, a[2] = 7, a[3] = 9, a[4] = 12;
  b[0] = 7, b[1] = 4, b[2] = 7, b[3] = 9, b[4] = 12, b[5] = 13;
  auto& cells = at(plan->map.basin_cells);
  cells.clear();
  for (const auto* r : {&none, &none, &a, &b, &a, &none})
    cells.insert(cells.end(), r->begin(), r->end());
  at(plan->map.undecided_reason) = {1.0, 0.0, 0.0, 0.0, 0.0, 3.0};
  compact_basin(*plan, block);
  const ExpandedBasin provisional(*plan, block);
  // The fixed point's lane keeps its settlement's number (1 of 2); the recurrence lanes number
  // the entries after the settlements: A (3), B (4), each with a copy of its settlement.
  EXPECT_EQ(at(plan->map.basin), (std::vector<double>{0.0, 1.0, 3.0, 4.0, 3.0, 0.0}));
  EXPECT_EQ(at(plan->map.basin_records),
            (std::vector<double>{-1.0, 0.0, 1.0, 0.5, 0.5, 0.0, 0.5, 0.5, 0.0, 0.5, 0.5, 0.0}));
  std::vector<double> entries = a;
  entries.insert(entries.end(), b.begin(), b.end());
  EXPECT_EQ(bits(at(plan->map.basin_cells)), bits(entries));
  // Unsettled lanes per reason (kUndecidedReasons), then each entry's reason.
  EXPECT_EQ(at(plan->map.undecided_reason),
            (std::vector<double>{0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(recurrence_record_of(*plan, block, 4)[1], 3.0);
  EXPECT_EQ(recurrence_record_of(*plan, block, 3)[1], 4.0);
  EXPECT_TRUE(std::isnan(recurrence_record_of(*plan, block, 1)[0]));
  // Labelled: lanes 1 and 3 on no attractor (label 0) count as "settled on none" (reason 0).
  EXPECT_EQ(undecided_counts(*plan, block, {0.0, 0.0, 1.0, 0.0, 1.0, 0.0}),
            (std::vector<std::int64_t>{2, 1, 0, 1, 0, 0, 0}));
}

// A lane settled by a fixed-point mapper on the block's last settlement record keeps that
// record's number and has no entry (lane_records.hpp): its record reads as none (NaN), and
// labelled 0 it counts as settled on no attractor (reason 0).
TEST(LaneRecords, FixedPointLaneOnTheLastSettlementHasNoEntry) {
  const RunSpec spec = parse_run_spec(kSpec, {"grid.q_0.n=2", "grid.p_0.n=3"}, "test spec");
  const auto plan = plan_of(spec);
  ASSERT_GE(plan->map.basin_cells, 0);
  BlockResults block({0, 3}, plan->columns);
  const auto at = [&](int c) -> std::vector<double>& {
    return block.columns[static_cast<std::size_t>(c)];
  };
  // Settlements: a recurrence's cell centre (period 0), then a fixed point (period 1), the last.
  at(plan->map.basin_records) = {0.5, 0.5, 0.0, -1.0, 0.0, 1.0};
  // Lanes: settled by recurrences (record a), on the fixed point, unsettled (no recurrence).
  at(plan->map.basin) = {1.0, 2.0, 0.0};
  std::vector<double> none(RecurrenceSearch::kRecordWidth, std::nan("")), a = none;
  a[0] = 7, a[1] = 3, a[2] = 7, a[3] = 9, a[4] = 12;
  auto& cells = at(plan->map.basin_cells);
  cells.clear();
  for (const auto* r : {&a, &none, &none}) cells.insert(cells.end(), r->begin(), r->end());
  at(plan->map.undecided_reason) = {0.0, 0.0, 1.0};
  compact_basin(*plan, block);
  ASSERT_TRUE(block.records_compacted);
  const ExpandedBasin provisional(*plan, block);
  // The fixed point's lane keeps 2 (of 2 settlements); record a is entry 3.
  EXPECT_EQ(at(plan->map.basin), (std::vector<double>{3.0, 2.0, 0.0}));
  EXPECT_EQ(recurrence_record_of(*plan, block, 0)[1], 3.0);
  const double* fixed = recurrence_record_of(*plan, block, 1);
  for (int k = 0; k < RecurrenceSearch::kRecordWidth; ++k) EXPECT_TRUE(std::isnan(fixed[k])) << k;
  EXPECT_EQ(undecided_counts(*plan, block, {1.0, 0.0, 0.0}),
            (std::vector<std::int64_t>{1, 1, 0, 0, 0, 0, 0}));
}

// Attractors found by recurrences are joined by their cells only (recurrence_table.hpp): two
// fixed points, each located in one cell of its own, far apart, stay two attractors although
// their records give the same located count (record[1], a count and not a cell). Each names as
// its source the smallest grid index of its lanes, and has its smallest cell's centre as point.
TEST(LaneRecords, RecurrenceAttractorsAreJoinedByTheirCellsOnly) {
  const RunSpec spec = parse_run_spec(kSpec, {"grid.q_0.n=2", "grid.p_0.n=3"}, "test spec");
  const auto plan = plan_of(spec);
  const RecurrenceSearch& r = plan->recurrence;
  ASSERT_EQ(r.cells.size(), 2u);
  ASSERT_GE(r.cells[0], 8);
  // Cell (i, j) along q (the fastest) and p has the key i + cells_q·j (cell_grid.hpp).
  const std::int64_t row = r.cells[1] / 2;
  const auto key = [&](std::int64_t i) { return static_cast<std::uint64_t>(i + r.cells[0] * row); };
  const std::uint64_t left = key(2), right = key(r.cells[0] - 3);
  std::vector<double> records;
  std::vector<std::size_t> offsets;
  const auto add = [&](double source, std::uint64_t cell) {
    offsets.push_back(records.size());
    records.insert(records.end(), {source, 0.0, 0.0, 0.0, 0.0});  // head, a point (not read)
    std::vector<double> record(RecurrenceSearch::kRecordWidth, std::nan(""));
    record[0] = static_cast<double>(cell), record[1] = 1.0, record[2] = static_cast<double>(cell);
    records.insert(records.end(), record.begin(), record.end());
  };
  add(40.0, left);
  add(12.0, left);
  add(7.0, right);
  std::vector<Attractor> table;
  add_recurrence_attractors(*plan, records, offsets, table);
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table[0].cells, (std::vector<std::uint64_t>{left}));
  EXPECT_EQ(table[1].cells, (std::vector<std::uint64_t>{right}));
  EXPECT_EQ(table[0].source, 12);
  EXPECT_EQ(table[1].source, 7);
  EXPECT_EQ(table[0].period, 0);
  // The centre of cell (2, row): lower + (index + 1/2)·size, to rounding (4 ulps: the sum may
  // round differently from however the code groups it).
  ASSERT_EQ(table[0].point.size(), 2u);
  EXPECT_DOUBLE_EQ(table[0].point[0], r.lower[0] + 2.5 * r.cell_size[0]);
  EXPECT_DOUBLE_EQ(table[0].point[1],
                   r.lower[1] + (static_cast<double>(row) + 0.5) * r.cell_size[1]);
}

// A block whose lanes nearly all differ in their records (a strange attractor's sketches) would
// cost more as entries (a record, a settlement's copy and a reason each: 14 values with one dof)
// than as per-point columns (11 values a lane): it keeps the per-point layout, so that layout
// bounds what any block holds (the memory check counts it).
TEST(LaneRecords, BlockWhoseEntriesWouldCostMoreKeepsItsPerPointRecords) {
  const RunSpec spec = parse_run_spec(kSpec, {"grid.q_0.n=2", "grid.p_0.n=3"}, "test spec");
  const auto plan = plan_of(spec);
  BlockResults block({0, 6}, plan->columns);
  const auto at = [&](int c) -> std::vector<double>& {
    return block.columns[static_cast<std::size_t>(c)];
  };
  at(plan->map.basin_records) = {0.5, 0.5, 0.0};
  at(plan->map.basin) = {1.0, 1.0, 1.0, 1.0, 1.0, 0.0};  // 5 distinct records: 70 > 66 values
  auto& cells = at(plan->map.basin_cells);
  cells.assign(6 * RecurrenceSearch::kRecordWidth, std::nan(""));
  for (std::size_t i = 0; i < 5; ++i) {
    double* record = &cells[i * RecurrenceSearch::kRecordWidth];
    record[0] = 7.0, record[1] = 3.0 + static_cast<double>(i);
  }
  at(plan->map.undecided_reason) = {0.0, 0.0, 0.0, 0.0, 0.0, 2.0};
  const std::vector<double> records = cells;
  compact_basin(*plan, block);
  EXPECT_FALSE(block.records_compacted);
  EXPECT_EQ(bits(at(plan->map.basin_cells)), bits(records));
  EXPECT_EQ(at(plan->map.basin_records), (std::vector<double>{0.5, 0.5, 0.0}));
  const ExpandedBasin provisional(*plan, block);
  EXPECT_EQ(at(plan->map.basin), (std::vector<double>{1.0, 1.0, 1.0, 1.0, 1.0, 0.0}));
  EXPECT_EQ(recurrence_record_of(*plan, block, 3)[1], 6.0);
  EXPECT_EQ(undecided_counts(*plan, block, at(plan->map.basin)),
            (std::vector<std::int64_t>{0, 0, 1, 0, 0, 0, 0}));
}

// A whole map in blocks: once from the per-point columns, once compacted as a run holds them.
struct Outcome {
  std::vector<double> candidates, labels;
  AttractorTable table;
  std::vector<std::int64_t> undecided = std::vector<std::int64_t>(kUndecidedReasons, 0);
  std::size_t entries = 0, lanes = 0, settled = 0;
};

Outcome map_in_blocks(const RunPlan& plan, std::int64_t size, bool compact) {
  std::vector<std::unique_ptr<BlockResults>> blocks;
  Outcome out;
  for (std::int64_t b = 0; b < plan.grid.size(); b += size) {
    blocks.push_back(std::make_unique<BlockResults>(
        PointRange{b, std::min(plan.grid.size(), b + size)}, plan.columns));
    run_block(plan, *blocks.back());
    for (double v : blocks.back()->columns[static_cast<std::size_t>(plan.map.basin)])
      out.settled += v != 0.0;
    if (compact) compact_basin(plan, *blocks.back());
    out.lanes += static_cast<std::size_t>(blocks.back()->range.end - b);
    out.entries += blocks.back()->columns[static_cast<std::size_t>(plan.map.basin_cells)].size() /
                   RecurrenceSearch::kRecordWidth;
  }
  for (auto& block : blocks) {
    const ExpandedBasin provisional(plan, *block);
    const std::vector<double> c = block_candidates(plan, *block);
    out.candidates.insert(out.candidates.end(), c.begin(), c.end());
  }
  out.table = merge_candidates(plan, out.candidates);
  for (auto& block : blocks) {
    const ExpandedBasin labels(plan, *block, true);
    const std::vector<double> provisional =
        block->columns[static_cast<std::size_t>(plan.map.basin)];
    label_block(plan, out.table.attractors, *block, out.table.along);
    count_undecided(plan, *block, provisional, out.undecided.data());
    const auto& l = block->columns[static_cast<std::size_t>(plan.map.basin)];
    out.labels.insert(out.labels.end(), l.begin(), l.end());
  }
  return out;
}

void expect_same_bits(const Outcome& got, const Outcome& want) {
  EXPECT_EQ(bits(got.candidates), bits(want.candidates));
  EXPECT_EQ(bits(got.labels), bits(want.labels));
  EXPECT_EQ(got.undecided, want.undecided);
  ASSERT_EQ(got.table.attractors.size(), want.table.attractors.size());
  for (std::size_t k = 0; k < want.table.attractors.size(); ++k) {
    const Attractor &x = got.table.attractors[k], &y = want.table.attractors[k];
    EXPECT_EQ(x.label, y.label);
    EXPECT_EQ(x.period, y.period);
    EXPECT_EQ(bits(x.point), bits(y.point));
    EXPECT_EQ(x.cells, y.cells);
    EXPECT_EQ(x.source, y.source);
  }
}

TEST(LaneRecords, CompactedBlocksGiveTheSameTableLabelsAndReasons) {
  const RunSpec spec = parse_run_spec(kSpec, {}, "test spec");
  const auto plan = plan_of(spec);
  ASSERT_GE(plan->map.basin_cells, 0);
  const Outcome whole = map_in_blocks(*plan, 96, false);
  const Outcome compact = map_in_blocks(*plan, 96, true);
  expect_same_bits(compact, whole);
  // Not a vacuous map: attractors by recurrences and by a fixed point, labelled and undecided
  // lanes; and far fewer entries than settled lanes.
  int by_cells = 0, fixed = 0;
  for (const Attractor& a : whole.table.attractors) (a.period == 0 ? by_cells : fixed) += 1;
  std::int64_t undecided = 0;
  for (double l : whole.labels) undecided += l == 0.0;
  EXPECT_GE(by_cells, 1);
  EXPECT_GE(fixed, 1);
  EXPECT_GT(undecided, 0);
  EXPECT_LT(undecided, static_cast<std::int64_t>(whole.labels.size()));
  std::int64_t counted = 0;
  for (std::int64_t n : whole.undecided) counted += n;
  EXPECT_EQ(counted, undecided);
  EXPECT_EQ(whole.entries, whole.lanes);            // per point: a record a lane
  EXPECT_LT(compact.entries * 4, compact.settled);  // 38 of 516 settled lanes when written

  // Blocks of one lane: those settled by recurrences keep their per-point record (one entry
  // would cost more), the others are compacted; the outcome is the same bits.
  const Outcome single = map_in_blocks(*plan, 1, false);
  const Outcome mixed = map_in_blocks(*plan, 1, true);
  expect_same_bits(mixed, single);
  EXPECT_LT(mixed.entries, mixed.lanes);  // some blocks compacted (no entry kept)...
  EXPECT_GT(mixed.entries, 0u);           // ... and some kept their record
}

}  // namespace
}  // namespace cs
