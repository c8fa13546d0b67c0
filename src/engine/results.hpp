// Results of a run, as columns: one per output dataset, `width` values per grid point
// (1, or the number of trajectory samples). Values are kept as doubles in the engine and
// converted to the dataset's element type when written.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "io/output_file.hpp"

namespace cs {

// One output dataset: its HDF5 description and how many values each point has.
struct ColumnSpec {
  DatasetSpec dataset;
  std::int64_t width = 1;
  bool internal = false;  // kept in the journal, never written to the output
  bool per_block = false;  // internal: `width` values for the whole block, not for each point
  bool grows = false;      // per block: starts empty and grows as the block runs (any length)
};

// Whole numbers (a basin map's labels) in the narrowest type that holds them all: 1, 2 or 4
// bytes a value instead of a double's 8 (engine/basin_column.hpp). Its members are defined in
// results.cpp: every kernel built at run time includes this header, and inline here their
// std::visit and the three vectors' members were instantiated in each kernel's compile, unused
// (about 0.05 s of its compiler CPU).
class CompactColumn {
 public:
  void assign(const std::vector<double>& values);
  void expand(std::vector<double>& out) const;
  std::size_t size() const;
  void clear();

 private:
  std::variant<std::vector<std::int8_t>, std::vector<std::int16_t>, std::vector<std::int32_t>> data_;
};

// The values of every column for one contiguous range of points.
struct BlockResults {
  PointRange range;
  std::vector<std::vector<double>> columns;  // in the plan's column order
  std::int64_t lane_steps = 0;  // steps its lanes were integrated (not journalled: 0 if loaded)
  // Where a running block adds the lane-steps it integrates, chunk by chunk, and takes them out
  // again when it ends (parallel/progress.hpp): progress inside a block that runs for hours.
  std::atomic<std::int64_t>* in_flight_steps = nullptr;

  std::vector<char> grows;  // per column: ColumnSpec::grows (the journal reads any length)
  // `basin` once the block is saved and streamed (compact_basin): its column is then empty.
  CompactColumn compact_basin;
  bool basin_compacted = false;
  // The recurrence mapper's records held per distinct entry (engine/recurrence/lane_records.hpp);
  // false when the block's entries would cost more than its per-point records.
  bool records_compacted = false;

  // Zeros, each column at its length for the range (results.cpp: the program makes blocks, the
  // kernels only fill them).
  BlockResults(PointRange r, const std::vector<ColumnSpec>& specs);
};

}  // namespace cs
