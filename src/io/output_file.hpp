// The HDF5 result file, written collectively by all MPI ranks (parallel HDF5, Open MPI build).
//
// Layout (INTERFACE.md): one 1-D coordinate dataset per grid axis, attached as a dimension scale;
// an optional time coordinate `t`; measure datasets with dims (axes..., [t]); CF-style attributes.
// The file is readable as netCDF-4 by xarray (engine="h5netcdf").
//
// Crash safety: the file is built under a temporary name next to the final one and renamed into
// place by commit(); a run that fails or is killed never leaves a file under the final name.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace cs {

enum class ElementType { float64, int8, uint8 };

struct DatasetSpec {
  std::string name;            // "final_q", "basin", "traj_q", ...
  ElementType type = ElementType::float64;
  bool has_time_dim = false;   // dims (axes..., t) instead of (axes...)
  std::string long_name;
  std::string units;           // omitted when empty
  std::vector<int> flag_values;            // for labels (status, basin); omitted when empty
  std::string flag_meanings;               // space-separated, CF style
  std::optional<double> fill_value;        // _FillValue, when cells can be missing
};

struct CoordinateSpec {
  std::string name;            // "q_0", "gamma", "t"
  std::vector<double> values;
  std::string long_name;
  std::string units;
};

struct FileLayout {
  std::vector<CoordinateSpec> axes;         // grid axes, first varies slowest; may be empty
  std::optional<CoordinateSpec> time;       // present iff some dataset has_time_dim
  std::vector<DatasetSpec> datasets;
  std::map<std::string, std::string> text_attributes;     // root attributes
  std::map<std::string, double> number_attributes;        // root attributes
};

// A contiguous run [begin, end) of flattened grid points (row-major over the axes).
struct PointRange {
  std::int64_t begin = 0;
  std::int64_t end = 0;
};

class OutputFile {
 public:
  // Collective. Creates `final_path + ".partial"` (replacing a stale one) with every dataset.
  // Throws std::runtime_error naming the path on failure.
  OutputFile(const std::string& final_path, const FileLayout& layout, MPI_Comm comm);
  ~OutputFile();  // closes and removes the temporary file unless commit() ran
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Collective: every rank calls it for every dataset, possibly with no ranges.
  // `ranges` are this rank's point ranges, sorted and disjoint; `data` holds their values
  // back to back in that order (times the length of `t` for time datasets), in the dataset's
  // element type.
  void write(const std::string& dataset, const std::vector<PointRange>& ranges, const void* data);

  // Collective: flush, close, and atomically rename to the final path.
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cs
