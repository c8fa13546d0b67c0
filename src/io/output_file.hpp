// The HDF5 result file, written by one process (rank 0: parallel/output_assembly.hpp says why)
// through HDF5's serial driver.
//
// Layout (INTERFACE.md): one 1-D coordinate dataset per grid axis, attached as a dimension scale;
// an optional time coordinate `t`; measure datasets with dims (axes..., [t]); CF-style attributes.
// The file is readable as netCDF-4 by xarray (engine="h5netcdf").
//
// Crash safety: the file is built under a temporary name next to the final one and put in place
// by commit(); a run that fails or is killed never leaves a file under the final name.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cs {

// int16 and int32 hold attractor labels past int8's 127 (basin_summary.cpp).
enum class ElementType { float64, int8, uint8, int16, int32 };

struct DatasetSpec {
  std::string name;            // "final_q", "basin", "traj_q", ...
  ElementType type = ElementType::float64;
  bool has_time_dim = false;   // dims (axes..., t) instead of (axes...)
  std::string long_name;
  std::string units;           // omitted when empty
  std::vector<int> flag_values;            // for labels (status, basin); omitted when empty
  std::string flag_meanings;               // space-separated, CF style
  std::optional<double> fill_value;        // _FillValue, when cells can be missing
  // Value of cells never written, as HDF5's fill value but without a _FillValue attribute, so
  // that readers keep an integer type (xarray turns masked integers into floats). For labels
  // whose type has no NaN: `status` fills with not_computed, never with 0 = ok.
  std::optional<double> unwritten_value = std::nullopt;
};

// A coordinate's values: its own, or a view of values that outlive every layout made of them
// (the plan's grid axes and sample times). A 1-D plane's axis is as long as the grid, and a
// copy of it per layout held it twice (2^25 points: 268 MB more on rank 0).
class CoordinateValues {
 public:
  CoordinateValues() = default;
  CoordinateValues(std::vector<double> values)  // NOLINT(google-explicit-constructor): as a vector
      : owned_(std::make_shared<const std::vector<double>>(std::move(values))), view_(*owned_) {}
  CoordinateValues(std::initializer_list<double> values) : CoordinateValues(std::vector<double>(values)) {}
  static CoordinateValues borrowed(std::span<const double> values) {
    CoordinateValues v;
    v.view_ = values;
    return v;
  }
  std::size_t size() const { return view_.size(); }
  bool empty() const { return view_.empty(); }
  const double* data() const { return view_.data(); }
  auto begin() const { return view_.begin(); }
  auto end() const { return view_.end(); }
  double operator[](std::size_t i) const { return view_[i]; }

 private:
  std::shared_ptr<const std::vector<double>> owned_;  // copies share it: the view stays valid
  std::span<const double> view_;
};

struct CoordinateSpec {
  std::string name;            // "q_0", "gamma", "t"
  CoordinateValues values;
  std::string long_name;
  std::string units;
};

// A small dataset given whole when the file is made (the attractor table, fractions along an
// axis): over named dimensions, each a grid axis or one of the layout's extra dimensions.
struct TableSpec {
  DatasetSpec dataset;              // name, type and attributes (has_time_dim unused)
  std::vector<std::string> dims;
  std::vector<double> values;       // row-major, the product of the dims' lengths
};

struct FileLayout {
  std::vector<CoordinateSpec> axes;         // grid axes, first varies slowest; may be empty
  std::optional<CoordinateSpec> time;       // present iff some dataset has_time_dim
  std::vector<DatasetSpec> datasets;
  std::vector<CoordinateSpec> extra_dimensions;  // e.g. `attractor`; may have length 0
  std::vector<TableSpec> tables;
  std::map<std::string, std::string> text_attributes;     // root attributes
  std::map<std::string, double> number_attributes;        // root attributes
};

// The first name a layout gives to two of its axes, datasets and tables ("" if none): checked
// before a run's work (output_assembly.hpp), so that a K parameter named like a dataset is bad
// input, not a failure after the work.
std::string repeated_name(const FileLayout& layout);

// A contiguous run [begin, end) of flattened grid points (row-major over the axes).
struct PointRange {
  std::int64_t begin = 0;
  std::int64_t end = 0;
};

class OutputFile {
 public:
  // Creates `final_path + ".partial"` (replacing a stale one) with every dataset. Throws
  // std::runtime_error naming the path on failure. No MPI call.
  OutputFile(const std::string& final_path, const FileLayout& layout);
  // Streaming (parallel/block_stream.hpp): creates only the root attributes, axes, time and
  // `layout.datasets`, so that blocks can be written as they are computed; complete() adds
  // what needs the whole map (the attractor table, statistics) before the commit.
  struct DatasetsFirst {};
  OutputFile(const std::string& final_path, const FileLayout& layout, DatasetsFirst);
  ~OutputFile();  // closes and removes the temporary file unless commit() ran
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // `ranges` are point ranges, sorted and disjoint, possibly none; `data` holds their values
  // back to back in that order (times the length of `t` for time datasets), in the dataset's
  // element type.
  void write(const std::string& dataset, const std::vector<PointRange>& ranges, const void* data);

  // After the DatasetsFirst constructor, once: `whole` is the layout the file would have been
  // created with. Adds its extra dimensions, tables and root attributes the file lacks, and
  // redefines each dataset whose description changed (`basin` once its labels are known: its
  // attributes; its type, a dataset never written yet, recreated, when they outgrow int8).
  // Objects are created in the order the one-step constructor creates them.
  void complete(const FileLayout& whole);

  // Optionally before complete(), with the same layout: redefines the datasets as complete()
  // would, and nothing else, so that `basin` is written, and read back for its statistics, in
  // its final type before the tables and attributes that hold them are created.
  void complete_datasets(const FileLayout& whole);

  // The values of a per-point dataset without a time dimension over the points `range`, as
  // int32 (`basin`'s labels, whatever its type): `out` holds range.end − range.begin values.
  void read(const std::string& dataset, PointRange range, std::int32_t* out) const;

  // Flush, close, sync the file, put it under the final path and sync the directory.
  // Without `replace_existing`, a file already at the final path is never replaced: the commit
  // fails instead (the caller's journal keeps the results).
  void commit(bool replace_existing = false);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Whether HDF5 still holds a file open: after a close that failed (a full disk met by HDF5's
// metadata flush, which it cannot recover from). HDF5 flushes such a file again inside
// MPI_Finalize and crashes there, so main() then ends the process without finalizing.
bool hdf5_files_left_open();

}  // namespace cs
