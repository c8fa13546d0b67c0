// A file created DatasetsFirst, completed at the end of a streamed run (output_file.hpp):
// `basin` redefined once its labels are known, the extra dimensions, tables and root
// attributes the file still lacks, created in the order the one-step constructor uses.
#include <hdf5.h>
#include <hdf5_hl.h>

#include <cstdint>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include "io/output_file.hpp"
#include "io/output_file_impl.hpp"
#include "io/point_boxes.hpp"

namespace cs {
using namespace hdf5;

static bool same_description(const DatasetSpec& a, const DatasetSpec& b) {
  return a.name == b.name && a.type == b.type && a.has_time_dim == b.has_time_dim &&
         a.long_name == b.long_name && a.units == b.units && a.flag_values == b.flag_values &&
         a.flag_meanings == b.flag_meanings && a.fill_value == b.fill_value &&
         a.unwritten_value == b.unwritten_value;
}

// A dataset whose description is known only at the end (`basin`): same type and fill, its
// attributes replaced; else (labels past int8), never written yet, it is made again under its
// name. That moves it last in creation order, behind the datasets created before it.
void OutputFile::Impl::redefine(std::size_t index, const DatasetSpec& spec) {
  Dataset& old = datasets[index];
  const std::string what = "cannot redefine dataset '" + spec.name + "'";
  if (old.spec.type == spec.type && old.spec.has_time_dim == spec.has_time_dim &&
      old.spec.fill_value == spec.fill_value && old.spec.unwritten_value == spec.unwritten_value) {
    for (const char* name : {"long_name", "units", "flag_values", "flag_meanings", "_FillValue"}) {
      const htri_t exists = checker(H5Aexists(old.handle.get(), name), what);
      if (exists > 0) checker(H5Adelete(old.handle.get(), name), what);
    }
    write_dataset_attributes(old.handle.get(), spec);
    old.spec = spec;
    return;
  }
  for (std::size_t d = 0; d < grid_dims.size(); ++d)
    checker(H5DSdetach_scale(old.handle.get(), coordinates[d].get(), static_cast<unsigned>(d)), what);
  if (old.spec.has_time_dim)
    checker(H5DSdetach_scale(old.handle.get(), coordinates.back().get(),
                             static_cast<unsigned>(grid_dims.size())), what);
  checker.require(old.handle.close(), what);
  checker(H5Ldelete(file.get(), spec.name.c_str(), H5P_DEFAULT), what);
  datasets.erase(datasets.begin() + static_cast<std::ptrdiff_t>(index));
  create_dataset(spec);
}

void OutputFile::Impl::create_late(const FileLayout& layout) {
  int dim_id = next_dim_id;
  for (const CoordinateSpec& extra : layout.extra_dimensions)
    extra_coordinates.push_back(create_coordinate(extra, dim_id++));
  for (const TableSpec& table : layout.tables) create_table(layout, table);
}

void OutputFile::Impl::create_table(const FileLayout& layout, const TableSpec& table) {
  const DatasetSpec& spec = table.dataset;
  const std::string what = "cannot create dataset '" + spec.name + "'";
  std::vector<hsize_t> shape;
  std::vector<hid_t> scales;
  for (const std::string& dim : table.dims) {
    for (std::size_t a = 0; a < layout.axes.size(); ++a)
      if (layout.axes[a].name == dim) shape.push_back(grid_dims[a]), scales.push_back(coordinates[a].get());
    for (std::size_t e = 0; e < layout.extra_dimensions.size(); ++e)
      if (layout.extra_dimensions[e].name == dim)
        shape.push_back(layout.extra_dimensions[e].values.size()),
            scales.push_back(extra_coordinates[e].get());
  }
  const hsize_t elements =
      std::accumulate(shape.begin(), shape.end(), hsize_t{1}, std::multiplies<>());
  if (shape.size() != table.dims.size() || elements != table.values.size())
    fail_here(what + ": its dimensions do not match its values");
  SpaceHandle space(checker(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), what));
  PropertyHandle dcpl = dataset_creation_properties(shape, spec.type, spec.fill_value);
  DatasetHandle dataset(checker(H5Dcreate2(file.get(), spec.name.c_str(), file_type(spec.type),
                                           space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), what));
  const auto as = [&]<class T>(std::vector<T>& out) {
    out.assign(table.values.begin(), table.values.end());
    return static_cast<const void*>(out.data());
  };
  std::vector<std::int8_t> i8;
  std::vector<std::uint8_t> u8;
  std::vector<std::int16_t> i16;
  std::vector<std::int32_t> i32;
  const void* data = static_cast<const void*>(table.values.data());
  switch (spec.type) {
    case ElementType::int8: data = as(i8); break;
    case ElementType::uint8: data = as(u8); break;
    case ElementType::int16: data = as(i16); break;
    case ElementType::int32: data = as(i32); break;
    case ElementType::float64: break;
  }
  write_whole(dataset.get(), elements, memory_type(spec.type), data, spec.name, what);
  for (std::size_t d = 0; d < scales.size(); ++d)
    checker(H5DSattach_scale(dataset.get(), scales[d], static_cast<unsigned>(d)),
            what + ": cannot attach its dimension scale");
  write_descriptive_attributes(dataset.get(), spec.long_name, spec.units, checker);
  if (!spec.flag_values.empty())  // attractor_kind; the tables that had none keep none
    write_flag_values(dataset.get(), spec.flag_values, spec.type, checker);
  if (!spec.flag_meanings.empty())
    write_text_attribute(dataset.get(), "flag_meanings", spec.flag_meanings, checker);
  tables.push_back(std::move(dataset));
}

void OutputFile::complete_datasets(const FileLayout& whole) {
  Impl& s = *impl_;
  if (!s.incomplete) fail(s.partial_path, "complete_datasets() without DatasetsFirst, or after complete()");
  s.validate(whole);
  if (whole.datasets.size() != s.datasets.size())
    fail(s.partial_path, "complete(): the datasets differ from the file's");
  for (const DatasetSpec& spec : whole.datasets) {
    std::size_t index = 0;
    while (index < s.datasets.size() && s.datasets[index].spec.name != spec.name) ++index;
    if (index == s.datasets.size())
      fail(s.partial_path, "complete(): no dataset named '" + spec.name + "'");
    if (!same_description(s.datasets[index].spec, spec)) s.redefine(index, spec);
  }
}

void OutputFile::complete(const FileLayout& whole) {
  Impl& s = *impl_;
  if (!s.incomplete) fail(s.partial_path, "complete() without DatasetsFirst, or twice");
  complete_datasets(whole);  // nothing left to do if the caller did it first
  for (const auto& [name, value] : whole.text_attributes)
    if (!s.written_text.contains(name)) write_text_attribute(s.file.get(), name, value, s.checker);
  for (const auto& [name, value] : whole.number_attributes)
    if (!s.written_numbers.contains(name))
      write_number_attribute(s.file.get(), name, value, s.checker);
  s.create_late(whole);
  s.incomplete = false;
}

// Box by box, as written (output_file.cpp's write_box_by_box says why), converted by HDF5.
void OutputFile::read(const std::string& name, PointRange range, std::int32_t* out) const {
  const Impl& s = *impl_;
  const Impl::Dataset* target = s.find(name);
  const std::string what = "cannot read dataset '" + name + "' back";
  if (target == nullptr || target->spec.has_time_dim || range.begin < 0 || range.end > s.points ||
      range.begin > range.end)
    fail(s.partial_path, what + ": no such per-point dataset or range");
  if (range.begin == range.end) return;
  SpaceHandle file_space(s.checker(H5Dget_space(target->handle.get()), what));
  if (s.grid_dims.empty()) {  // a single trajectory: its one point
    const hsize_t one = 1;
    SpaceHandle mem_space(s.checker(H5Screate_simple(1, &one, nullptr), what));
    s.checker(H5Dread(target->handle.get(), H5T_NATIVE_INT32, mem_space.get(), file_space.get(),
                      H5P_DEFAULT, out), what);
    return;
  }
  for (const Box& box : boxes_of({range}, s.grid_dims, false, 0)) {
    s.checker(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, box.start.data(), nullptr,
                                  box.count.data(), nullptr), what);
    SpaceHandle mem_space(s.checker(
        H5Screate_simple(static_cast<int>(box.count.size()), box.count.data(), nullptr), what));
    s.checker(H5Dread(target->handle.get(), H5T_NATIVE_INT32, mem_space.get(), file_space.get(),
                      H5P_DEFAULT, out), what);
    out += elements_of(box);
  }
}

}  // namespace cs
