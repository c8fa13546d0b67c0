// The inside of OutputFile (io/output_file.hpp), shared by its two sources: output_file.cpp
// (creating the file, writing, committing) and output_completion.cpp (what a file created
// DatasetsFirst receives at the end). Nothing else includes it.
#pragma once

#include <sys/stat.h>

#include <hdf5.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/hdf5_objects.hpp"
#include "io/output_file.hpp"

namespace cs {

struct OutputFile::Impl {
  using Checker = hdf5::Checker;
  using DatasetHandle = hdf5::DatasetHandle;
  using FileHandle = hdf5::FileHandle;
  using PropertyHandle = hdf5::PropertyHandle;
  struct Dataset {
    DatasetSpec spec;
    DatasetHandle handle;
  };

  std::string final_path;
  std::string partial_path;
  std::vector<hsize_t> grid_dims;  // axis lengths, first slowest
  std::int64_t points = 1;         // product of grid_dims (1: a single trajectory)
  hsize_t time_length = 0;
  FileHandle file;
  std::vector<DatasetHandle> coordinates;  // axes..., then t
  std::vector<Dataset> datasets;
  std::vector<DatasetHandle> extra_coordinates, tables;
  Checker checker;  // every HDF5 result
  bool committed = false;
  bool incomplete = false;  // created DatasetsFirst, complete() not yet called
  int next_dim_id = 0;      // _Netcdf4Dimid of the first extra dimension
  std::map<std::string, std::string> written_text;  // DatasetsFirst: root attributes so far
  std::map<std::string, double> written_numbers;
  // The temporary file this run made (device and inode, from HDF5's descriptor): the name is put
  // in place, or removed, only while it is still that file. A run started beside this one (the
  // journal's lock is what keeps them apart, and a bug there once let one in) could otherwise
  // have this run publish its half-written file under the output's name.
  dev_t made_device = 0;
  ino_t made_inode = 0;
  bool made_known = false;

  [[noreturn]] void fail_here(const std::string& what, std::string detail = {}) const {
    hdf5::fail(partial_path, what, std::move(detail));
  }

  void validate(const FileLayout& layout) const;
  void create_file(const FileLayout& layout);
  PropertyHandle dataset_creation_properties(const std::vector<hsize_t>& shape, ElementType type,
                                             std::optional<double> fill) const;
  DatasetHandle create_coordinate(const CoordinateSpec& coordinate, int dim_id);
  void create_dataset(const DatasetSpec& spec);
  void write_dataset_attributes(hid_t dataset, const DatasetSpec& spec);
  void redefine(std::size_t index, const DatasetSpec& spec);
  void create_table(const FileLayout& layout, const TableSpec& table);
  void write_selected(hid_t dataset, hid_t mem_type, hid_t file_space, hid_t mem_space,
                      const void* data, const std::string& name) const;
  void write_whole(hid_t dataset, hsize_t elements, hid_t mem_type, const void* data,
                   const std::string& name, const std::string& what) const;
  std::vector<hsize_t> shape_of(const DatasetSpec& spec) const;
  const Dataset* find(const std::string& name) const;
  std::string request_problem(const std::string& name, const std::vector<PointRange>& ranges) const;
  void open(const std::string& final, const FileLayout& layout, bool datasets_first);
  void create(const FileLayout& layout, bool datasets_first = false);
  void create_late(const FileLayout& layout);
  void write(const Dataset& target, const std::vector<PointRange>& ranges, const void* data) const;
  void write_box_by_box(const Dataset& target, const std::vector<PointRange>& runs,
                        const void* data) const;
  bool flush();
  bool close_all();
  void abandon() noexcept;
  bool partial_is_ours() const;
};

}  // namespace cs
