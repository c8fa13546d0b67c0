// HDF5 writer for the result file (see output_file.hpp for the layout contract): one process,
// HDF5's serial (sec2) driver, no MPI call (parallel/output_assembly.hpp says why).
#include "io/output_file.hpp"

#include <hdf5.h>
#include <hdf5_hl.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "io/durable_file.hpp"
#include "io/hdf5_objects.hpp"
#include "io/output_file_impl.hpp"
#include "io/point_boxes.hpp"

namespace cs {
using namespace hdf5;
namespace {

// A file-system step around HDF5's: its error message, if any, names the file and the step.
template <typename Action>
void file_system_step(const std::string& path, const std::string& what, Action&& action) {
  try {
    action();
  } catch (const std::exception& e) {
    fail(path, what, e.what());
  }
}

// What the finished file takes on disk: every dataset and coordinate, plus room for metadata.
double expected_bytes(const FileLayout& layout) {
  double points = 1.0, coordinates = 0.0;
  for (const CoordinateSpec& axis : layout.axes) {
    points *= static_cast<double>(axis.values.size());
    coordinates += static_cast<double>(axis.values.size());
  }
  const double times = layout.time ? static_cast<double>(layout.time->values.size()) : 1.0;
  if (layout.time) coordinates += times;
  double bytes = coordinates * sizeof(double) + 65536.0;
  for (const DatasetSpec& d : layout.datasets)
    bytes += points * (d.has_time_dim ? times : 1.0) * static_cast<double>(element_size(d.type));
  return bytes;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::string repeated_name(const FileLayout& layout) {
  std::set<std::string> names;
  std::string repeated;
  const auto add = [&](const std::string& name) {
    if (!names.insert(name).second && repeated.empty()) repeated = name;
  };
  for (const CoordinateSpec& axis : layout.axes) add(axis.name);
  if (layout.time) add(layout.time->name);
  for (const CoordinateSpec& extra : layout.extra_dimensions) add(extra.name);
  for (const TableSpec& table : layout.tables) add(table.dataset.name);
  for (const DatasetSpec& spec : layout.datasets) add(spec.name);
  return repeated;
}

void OutputFile::Impl::validate(const FileLayout& layout) const {
  std::set<std::string> names;
  const auto add_name = [&](const std::string& name) {
    if (name.empty()) fail_here("a dataset or axis has an empty name");
    if (name.find('/') != std::string::npos) fail_here("name '" + name + "' contains '/'");
    if (!names.insert(name).second) fail_here("name '" + name + "' is used twice");
  };
  for (const CoordinateSpec& axis : layout.axes) {
    add_name(axis.name);
    if (axis.values.empty()) fail_here("axis '" + axis.name + "' has no values");
  }
  if (layout.time) add_name(layout.time->name);
  for (const CoordinateSpec& extra : layout.extra_dimensions) add_name(extra.name);
  for (const TableSpec& table : layout.tables) add_name(table.dataset.name);
  for (const DatasetSpec& spec : layout.datasets) {
    add_name(spec.name);
    if (spec.has_time_dim && !layout.time) {
      fail_here("dataset '" + spec.name + "' has a time dimension but the layout has no time");
    }
    for (int flag : spec.flag_values) {
      if (!representable(flag, spec.type)) {
        fail_here("flag value " + std::to_string(flag) + " of '" + spec.name +
                  "' does not fit its type");
      }
    }
    if ((spec.fill_value && !representable(*spec.fill_value, spec.type)) ||
        (spec.unwritten_value && !representable(*spec.unwritten_value, spec.type))) {
      fail_here("fill value of '" + spec.name + "' does not fit its type");
    }
  }
}

std::vector<hsize_t> OutputFile::Impl::shape_of(const DatasetSpec& spec) const {
  std::vector<hsize_t> shape = grid_dims;
  if (spec.has_time_dim) shape.push_back(time_length);
  return shape;
}

PropertyHandle OutputFile::Impl::dataset_creation_properties(const std::vector<hsize_t>& shape,
                                                             ElementType type,
                                                             std::optional<double> fill) const {
  const std::string what = "cannot set up dataset creation properties";
  PropertyHandle dcpl(checker(H5Pcreate(H5P_DATASET_CREATE), what));
  // No timestamps in object headers: two identical runs give byte-identical files.
  checker(H5Pset_obj_track_times(dcpl.get(), false), what);
  const hsize_t elements =
      std::accumulate(shape.begin(), shape.end(), hsize_t{1}, std::multiplies<>());
  // Scalars cannot be chunked, and chunk dims must not exceed fixed zero-length dims.
  if (!shape.empty() && elements > 0) {
    const std::vector<hsize_t> chunk = chunk_shape(shape, element_size(type));
    checker(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), what);
  }
  if (fill) {
    const TypedValue v = typed(*fill, type);
    checker(H5Pset_fill_value(dcpl.get(), memory_type(type), v.pointer(type)), what);
  }
  return dcpl;
}

void OutputFile::Impl::create_file(const FileLayout& layout) {
  const std::string what = "cannot create the file";
  PropertyHandle fapl(checker(H5Pcreate(H5P_FILE_ACCESS), what));
  checker(H5Pset_fapl_sec2(fapl.get()), what);
  PropertyHandle fcpl(checker(H5Pcreate(H5P_FILE_CREATE), what));
  checker(H5Pset_obj_track_times(fcpl.get(), false), what);  // root group
  // Creation order lets readers (h5py, h5netcdf, netCDF-C) list variables in layout order.
  checker(H5Pset_link_creation_order(fcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), what);
  // H5F_ACC_EXCL (O_CREAT | O_EXCL): a name planted since the stale one was removed, a link
  // above all, makes the create fail instead of writing through it.
  file = FileHandle(checker(H5Fcreate(partial_path.c_str(), H5F_ACC_EXCL, fcpl.get(), fapl.get()), what));
  void* handle = nullptr;
  struct stat made {};
  if (H5Fget_vfd_handle(file.get(), H5P_DEFAULT, &handle) >= 0 && handle != nullptr &&
      ::fstat(*static_cast<int*>(handle), &made) == 0)
    made_device = made.st_dev, made_inode = made.st_ino, made_known = true;
  for (const auto& [name, value] : layout.text_attributes) {
    write_text_attribute(file.get(), name, value, checker);
  }
  for (const auto& [name, value] : layout.number_attributes) {
    write_number_attribute(file.get(), name, value, checker);
  }
}

// Writes a whole dataset of `elements` values; an empty one (a dimension of length 0, such as
// `attractor` when nothing settled) with nothing selected.
void OutputFile::Impl::write_whole(hid_t dataset, hsize_t elements, hid_t mem_type,
                                   const void* data, const std::string& name,
                                   const std::string& what) const {
  SpaceHandle file_space(checker(H5Dget_space(dataset), what));
  SpaceHandle mem_space(checker(H5Screate_simple(1, &elements, nullptr), what));
  if (elements == 0) {
    checker(H5Sselect_none(file_space.get()), what);
    checker(H5Sselect_none(mem_space.get()), what);
  }
  write_selected(dataset, mem_type, file_space.get(), mem_space.get(), data, name);
}

// A 1-D float64 dataset named as its dimension, made a dimension scale: this is what netCDF-4
// (and so h5netcdf/xarray) reads as a dimension with a coordinate variable.
DatasetHandle OutputFile::Impl::create_coordinate(const CoordinateSpec& coordinate, int dim_id) {
  const std::string what = "cannot create coordinate '" + coordinate.name + "'";
  const hsize_t n = coordinate.values.size();
  SpaceHandle space(checker(H5Screate_simple(1, &n, nullptr), what));
  PropertyHandle dcpl = dataset_creation_properties({n}, ElementType::float64, std::nullopt);
  DatasetHandle dataset(checker(H5Dcreate2(file.get(), coordinate.name.c_str(), H5T_IEEE_F64LE,
                                         space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), what));
  write_whole(dataset.get(), n, H5T_NATIVE_DOUBLE, coordinate.values.data(), coordinate.name, what);
  checker(H5DSset_scale(dataset.get(), coordinate.name.c_str()), what);
  // netCDF-C numbers dimensions by this (h5netcdf hides it); harmless for other readers.
  SpaceHandle scalar(checker(H5Screate(H5S_SCALAR), what));
  write_attribute(dataset.get(), "_Netcdf4Dimid", H5T_STD_I32LE, H5T_NATIVE_INT, scalar.get(),
                  &dim_id, checker);
  write_descriptive_attributes(dataset.get(), coordinate.long_name, coordinate.units, checker);
  return dataset;
}

void OutputFile::Impl::create_dataset(const DatasetSpec& spec) {
  const std::string what = "cannot create dataset '" + spec.name + "'";
  const std::vector<hsize_t> shape = shape_of(spec);
  SpaceHandle space(
      checker(shape.empty() ? H5Screate(H5S_SCALAR)
                          : H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), what));
  std::optional<double> fill = spec.fill_value ? spec.fill_value : spec.unwritten_value;
  if (!fill && spec.type == ElementType::float64) fill = std::numeric_limits<double>::quiet_NaN();
  PropertyHandle dcpl = dataset_creation_properties(shape, spec.type, fill);
  DatasetHandle dataset(checker(H5Dcreate2(file.get(), spec.name.c_str(), file_type(spec.type),
                                         space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), what));
  for (std::size_t d = 0; d < grid_dims.size(); ++d) {
    checker(H5DSattach_scale(dataset.get(), coordinates[d].get(), static_cast<unsigned>(d)), what + ": cannot attach its dimension scale");
  }
  if (spec.has_time_dim) {
    checker(H5DSattach_scale(dataset.get(), coordinates.back().get(),
                           static_cast<unsigned>(grid_dims.size())), what + ": cannot attach the time scale");
  }
  write_dataset_attributes(dataset.get(), spec);
  datasets.push_back(Dataset{spec, std::move(dataset)});
}

void OutputFile::Impl::write_dataset_attributes(hid_t dataset, const DatasetSpec& spec) {
  write_descriptive_attributes(dataset, spec.long_name, spec.units, checker);
  if (!spec.flag_values.empty()) {
    write_flag_values(dataset, spec.flag_values, spec.type, checker);
  }
  if (!spec.flag_meanings.empty()) {
    write_text_attribute(dataset, "flag_meanings", spec.flag_meanings, checker);
  }
  if (spec.fill_value) {
    write_typed_attribute(dataset, "_FillValue", *spec.fill_value, spec.type, checker);
  }
}

void OutputFile::Impl::write_selected(hid_t dataset, hid_t mem_type, hid_t file_space,
                                      hid_t mem_space, const void* data,
                                      const std::string& name) const {
  checker(H5Dwrite(dataset, mem_type, mem_space, file_space, H5P_DEFAULT, data), "cannot write dataset '" + name + "'");
}

const OutputFile::Impl::Dataset* OutputFile::Impl::find(const std::string& name) const {
  for (const Dataset& d : datasets) {
    if (d.spec.name == name) return &d;
  }
  return nullptr;
}

// Closes datasets before the file: HDF5 keeps a file open past H5Fclose while objects in it are
// open (its default, weak close degree), and a close that fails must show here.
bool OutputFile::Impl::close_all() {
  bool ok = true;
  for (Dataset& d : datasets) ok = d.handle.close() && ok;
  for (DatasetHandle& c : coordinates) ok = c.close() && ok;
  for (DatasetHandle& t : tables) ok = t.close() && ok;
  for (DatasetHandle& c : extra_coordinates) ok = c.close() && ok;
  ok = file.close() && ok;
  return ok;
}

// HDF5 writes its cached metadata. Flushing before closing keeps a failure (a full disk) at a
// point where the file is still open and can be flushed again.
bool OutputFile::Impl::flush() {
  return !file.valid() || H5Fflush(file.get(), H5F_SCOPE_GLOBAL) >= 0;
}

// Never throws: the path of every failure (constructor, commit, a destructor called while an
// exception unwinds) ends here, so nothing is left under either name.
void OutputFile::Impl::abandon() noexcept {
  if (!flush()) {
    // The disk is full. Free what the file holds and flush again, so that HDF5 can close it
    // now; a file it failed to close stays open inside HDF5 (main.cpp then skips MPI_Finalize,
    // where HDF5 would try again and crash). Truncated through HDF5's own descriptor (the sec2
    // driver's), not by name: in a directory others can write to, the name may no longer be
    // the file we made.
    void* handle = nullptr;
    if (file.get() >= 0 && H5Fget_vfd_handle(file.get(), H5P_DEFAULT, &handle) >= 0 && handle != nullptr) {
      [[maybe_unused]] const int truncated = ::ftruncate(*static_cast<int*>(handle), 0);
    }
    flush();
  }
  close_all();
  hdf5_error_detail();  // clears the error stack
  std::error_code ignored;
  if (partial_is_ours()) std::filesystem::remove(partial_path, ignored);
}

bool OutputFile::Impl::partial_is_ours() const {
  if (!made_known) return true;  // HDF5 did not say (no sec2 descriptor): the name as before
  struct stat now {};
  return ::lstat(partial_path.c_str(), &now) == 0 && S_ISREG(now.st_mode) &&
         now.st_dev == made_device && now.st_ino == made_inode;
}

// Empty when the request is well formed, else the reason.
std::string OutputFile::Impl::request_problem(const std::string& name,
                                              const std::vector<PointRange>& ranges) const {
  if (committed) return final_path + ": write of '" + name + "' after commit";
  if (find(name) == nullptr) return partial_path + ": no dataset named '" + name + "'";
  std::int64_t previous_end = 0;
  for (const PointRange& r : ranges) {
    if (r.begin < previous_end || r.end < r.begin || r.end > points) {
      return partial_path + ": point ranges for '" + name +
             "' are not sorted, disjoint and inside [0, " + std::to_string(points) + ")";
    }
    previous_end = r.end;
  }
  return {};
}

void OutputFile::Impl::create(const FileLayout& layout, bool datasets_first) {
  validate(layout);
  for (const CoordinateSpec& axis : layout.axes) {
    grid_dims.push_back(axis.values.size());
    points *= static_cast<std::int64_t>(axis.values.size());
  }
  if (layout.time) time_length = layout.time->values.size();

  // A stale temporary from a killed run may be anything (read-only, even a directory); start
  // from nothing. remove() takes a link itself away, never what it points to, and fails on a
  // name another user owns in a shared (sticky) directory: then the run is refused.
  file_system_step(partial_path, "cannot remove the stale temporary file",
                   [&] { std::filesystem::remove(partial_path); });
  file_system_step(partial_path, "not enough room for the output",
                   [&] { check_room_for(partial_path, expected_bytes(layout)); });

  create_file(layout);
  int dim_id = 0;
  for (const CoordinateSpec& axis : layout.axes) {
    coordinates.push_back(create_coordinate(axis, dim_id++));
  }
  if (layout.time) coordinates.push_back(create_coordinate(*layout.time, dim_id++));
  for (const DatasetSpec& spec : layout.datasets) create_dataset(spec);
  next_dim_id = dim_id;
  if (datasets_first) {
    incomplete = true;
    written_text = layout.text_attributes;
    written_numbers = layout.number_attributes;
    return;
  }
  create_late(layout);
}

void OutputFile::Impl::write(const Dataset& target, const std::vector<PointRange>& ranges,
                             const void* data) const {
  const std::vector<PointRange> runs = merged(ranges);
  std::int64_t selected_points = 0;
  for (const PointRange& r : runs) selected_points += r.end - r.begin;
  const hsize_t per_point = target.spec.has_time_dim ? time_length : 1;
  const hsize_t elements = static_cast<hsize_t>(selected_points) * per_point;

  if (!grid_dims.empty() && elements > 0) {
    write_box_by_box(target, runs, data);
    return;
  }
  // No grid (a single trajectory: its one point selected whole), or nothing to write.
  const std::string what = "cannot select the points of '" + target.spec.name + "'";
  SpaceHandle file_space(checker(H5Dget_space(target.handle.get()), what));
  const hsize_t mem_dims = std::max<hsize_t>(elements, 1);  // keep the memory space non-empty
  SpaceHandle mem_space(checker(H5Screate_simple(1, &mem_dims, nullptr), what));
  if (elements == 0) {
    checker(H5Sselect_none(mem_space.get()), what);
    checker(H5Sselect_none(file_space.get()), what);
  } else {
    checker(H5Sselect_all(file_space.get()), what);
  }
  write_selected(target.handle.get(), memory_type(target.spec.type), file_space.get(),
                 mem_space.get(), data, target.spec.name);
}

// One process writes each box on its own, from a memory space of the box's shape. HDF5 maps a
// selection onto chunks box by box when memory and file selections have the same shape, but
// element by element otherwise (a 1-D buffer against a 2-D union of boxes): that cost the 512²
// basin map's six datasets ~30 ms, 7 % of its run on 2 threads. One call per box costs far less.
void OutputFile::Impl::write_box_by_box(const Dataset& target,
                                        const std::vector<PointRange>& runs,
                                        const void* data) const {
  const std::string what = "cannot write dataset '" + target.spec.name + "'";
  const auto* bytes = static_cast<const unsigned char*>(data);
  const std::size_t element_bytes = element_size(target.spec.type);
  SpaceHandle file_space(checker(H5Dget_space(target.handle.get()), what));
  for (const Box& box : boxes_of(runs, grid_dims, target.spec.has_time_dim, time_length)) {
    checker(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, box.start.data(), nullptr,
                                box.count.data(), nullptr), what);
    SpaceHandle mem_space(checker(
        H5Screate_simple(static_cast<int>(box.count.size()), box.count.data(), nullptr), what));
    write_selected(target.handle.get(), memory_type(target.spec.type), file_space.get(),
                   mem_space.get(), bytes, target.spec.name);
    bytes += elements_of(box) * element_bytes;
  }
}

// ---------------------------------------------------------------------------------------------

OutputFile::OutputFile(const std::string& final_path, const FileLayout& layout)
    : impl_(std::make_unique<Impl>()) {
  impl_->open(final_path, layout, false);
}

OutputFile::OutputFile(const std::string& final_path, const FileLayout& layout, DatasetsFirst)
    : impl_(std::make_unique<Impl>()) {
  impl_->open(final_path, layout, true);
}

void OutputFile::Impl::open(const std::string& final, const FileLayout& layout,
                            bool datasets_first) {
  final_path = final;
  partial_path = final + ".partial";
  // Failures become exceptions with a message; HDF5's own stderr dump would only add noise.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  checker = Checker(partial_path);
  try {
    create(layout, datasets_first);
  } catch (...) {
    abandon();  // the destructor does not run for a constructor that throws
    throw;
  }
}

OutputFile::~OutputFile() {
  if (impl_ && !impl_->committed) impl_->abandon();
}

void OutputFile::write(const std::string& dataset, const std::vector<PointRange>& ranges,
                       const void* data) {
  const std::string problem = impl_->request_problem(dataset, ranges);
  if (!problem.empty()) throw std::runtime_error(problem);
  impl_->write(*impl_->find(dataset), ranges, data);
}

void OutputFile::commit(bool replace_existing) {
  Impl& s = *impl_;
  if (s.committed) fail(s.final_path, "commit called twice");
  if (s.incomplete) fail(s.partial_path, "commit before complete()");
  s.checker.require(s.flush(), "cannot write the file's metadata");
  s.checker.require(s.close_all(), "cannot close the file");
  if (!s.partial_is_ours())
    fail(s.partial_path, "the temporary file this run wrote was removed or replaced by another "
                         "program; nothing was put in place (another run of this output?)");
  file_system_step(s.final_path, "cannot put the finished file in place",
                   [&] { place_durably(s.partial_path, s.final_path, replace_existing); });
  s.committed = true;
}

bool hdf5_files_left_open() {
  return H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE) > 0;
}

}  // namespace cs
