// OutputFile, as contactsweep writes (one process, box by box): ragged, adjacent and gappy point
// ranges; the committed file is read back with plain HDF5 and every cell checked against a
// function of its flat index, with the dimension scales, the attributes and the temporary-file
// protocol.
//
// The main file (and a scalar one next to it) are kept for tests/test_xarray_open.py: their path is
// $CONTACTSWEEP_TEST_OUT (run by hand without it: a private temporary directory, removed at exit).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <hdf5_hl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "io/output_file.hpp"
#include "support/hdf5_reading.hpp"
#include "support/private_temp_dir.hpp"

namespace {

using cs::test::attribute_has_type;
using cs::test::attribute_values;
using cs::test::expect_scales;
using cs::test::read_all;
using cs::test::Reader;
using cs::test::shape_of;
using cs::test::text_attribute;

using cs::CoordinateSpec;
using cs::DatasetSpec;
using cs::ElementType;
using cs::FileLayout;
using cs::OutputFile;
using cs::PointRange;

std::string output_path() {
  if (const char* path = std::getenv("CONTACTSWEEP_TEST_OUT"); path != nullptr && *path != '\0') {
    return path;
  }
  // Run by hand: a private directory of its own (a fixed name in /tmp may be another user's).
  static const cs::test::PrivateTempDir dir("contactsweep_output_test_");
  return dir.file("contactsweep_output_test.h5");
}

// Another file next to the main one: "<dir>/<stem>_<tag>.h5".
std::string sibling_path(const std::string& tag) {
  const std::filesystem::path main(output_path());
  return (main.parent_path() / (main.stem().string() + "_" + tag + ".h5")).string();
}

bool exists(const std::string& path) { return std::filesystem::exists(path); }

// Files, datasets, attributes and types still open anywhere: an OutputFile gone, on whatever
// path, must have closed everything it opened.
ssize_t open_hdf5_objects() { return H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL); }

void remove_both(const std::string& path) {
  std::filesystem::remove(path);
  std::filesystem::remove(path + ".partial");
}

std::vector<double> linspace(double from, double to, int n) {
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = from + (to - from) * i / (n - 1);
  return v;
}

// Blocks of sizes 1, 2, ..., max_block, 1, 2, ...: ragged and adjacent, so both merging and
// every kind of row boundary occur.
std::vector<PointRange> ragged_ranges(std::int64_t points, int max_block) {
  std::vector<PointRange> ranges;
  std::int64_t begin = 0;
  for (int block = 0; begin < points; ++block) {
    const std::int64_t end = std::min<std::int64_t>(points, begin + 1 + block % max_block);
    ranges.push_back({begin, end});
    begin = end;
  }
  return ranges;
}

// Like ragged_ranges, but only every other block is written: gaps between ranges, which start
// and end inside rows. written_in_gappy() tells which points those are.
std::vector<PointRange> gappy_ranges(std::int64_t points, int max_block) {
  std::vector<PointRange> ranges;
  std::int64_t begin = 0;
  for (int block = 0; begin < points; ++block) {
    const std::int64_t end = std::min<std::int64_t>(points, begin + 1 + block % max_block);
    if (block % 2 == 1) ranges.push_back({begin, end});
    begin = end;
  }
  return ranges;
}

bool written_in_gappy(std::int64_t point, int max_block) {
  std::int64_t begin = 0;
  for (int block = 0;; ++block) {
    const std::int64_t end = begin + 1 + block % max_block;
    if (point < end) return block % 2 == 1;
    begin = end;
  }
}

// The part of `ranges` below `limit`.
std::vector<PointRange> clipped(const std::vector<PointRange>& ranges, std::int64_t limit) {
  std::vector<PointRange> out;
  for (PointRange r : ranges) {
    r.end = std::min(r.end, limit);
    if (r.begin < r.end) out.push_back(r);
  }
  return out;
}

// Values of `ranges` back to back, `per_point` consecutive values per point.
template <typename T>
std::vector<T> values_for(const std::vector<PointRange>& ranges, std::int64_t per_point,
                          const std::function<T(std::int64_t, std::int64_t)>& f) {
  std::vector<T> out;
  for (const PointRange& r : ranges) {
    for (std::int64_t i = r.begin; i < r.end; ++i) {
      for (std::int64_t j = 0; j < per_point; ++j) out.push_back(f(i, j));
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Layouts.

DatasetSpec measure(const std::string& name, const std::string& long_name, bool time = false) {
  DatasetSpec spec;
  spec.name = name;
  spec.long_name = long_name;
  spec.has_time_dim = time;
  return spec;
}

DatasetSpec flags(const std::string& name, ElementType type, const std::string& long_name,
                  std::vector<int> values, const std::string& meanings) {
  DatasetSpec spec = measure(name, long_name);
  spec.type = type;
  spec.flag_values = std::move(values);
  spec.flag_meanings = meanings;
  return spec;
}

// The 2-axis layout (7 x 5, neither divisible by the block sizes) with a time axis.

constexpr std::int64_t kNq = 7;
constexpr std::int64_t kNgamma = 5;
constexpr std::int64_t kNt = 4;
constexpr std::int64_t kPoints = kNq * kNgamma;

double final_q(std::int64_t i, std::int64_t) { return 0.25 * static_cast<double>(i) - 3.0; }
double traj_q(std::int64_t i, std::int64_t j) { return 100.0 * static_cast<double>(i) + j; }
double settle_time(std::int64_t i, std::int64_t) { return 1.5 * static_cast<double>(i); }
std::uint8_t status_of(std::int64_t i, std::int64_t) { return static_cast<std::uint8_t>(i % 3); }
std::int8_t basin_of(std::int64_t i, std::int64_t) { return static_cast<std::int8_t>(i % 3 - 1); }

FileLayout grid_layout() {
  FileLayout layout;
  layout.axes.push_back({"q_0", linspace(-3.0, 3.0, kNq), "initial value of q", ""});
  layout.axes.push_back({"gamma", linspace(0.1, 0.5, kNgamma), "damping coefficient", ""});
  layout.time = CoordinateSpec{"t", linspace(0.0, 1.5, kNt), "time", "1"};
  DatasetSpec label =
      flags("label", ElementType::int8, "partly written label", {-1, 1}, "minus plus");
  label.fill_value = -128.0;
  layout.datasets = {
      measure("final_q", "q at t_end"),
      measure("traj_q", "q along the trajectory", /*time=*/true),
      measure("settle_time", "settling time"),
      flags("status", ElementType::uint8, "integration status", {0, 1, 2}, "ok diverged breakdown"),
      flags("basin", ElementType::int8, "basin of attraction", {-1, 0, 1},
            "left_well undecided right_well"),
      label,
  };
  layout.datasets[2].units = "1";
  layout.text_attributes = {
      {"title", "OutputFile test"}, {"Conventions", "CF-1.8"}, {"empty", ""}, {"x", "1"}};
  layout.number_attributes = {{"h", 0.01}, {"t_end", 1.5}};
  return layout;
}

// Writes every dataset of grid_layout(): settle_time and label only on the first half of the
// points, so the fill values must show in the other half.
void write_grid_file(const std::string& path) {
  const std::vector<PointRange> mine = ragged_ranges(kPoints, /*max_block=*/4);
  const std::vector<PointRange> half = clipped(mine, kPoints / 2);
  OutputFile out(path, grid_layout());
  out.write("final_q", mine, values_for<double>(mine, 1, final_q).data());
  out.write("traj_q", mine, values_for<double>(mine, kNt, traj_q).data());
  out.write("settle_time", half, values_for<double>(half, 1, settle_time).data());
  out.write("status", mine, values_for<std::uint8_t>(mine, 1, status_of).data());
  out.write("basin", mine, values_for<std::int8_t>(mine, 1, basin_of).data());
  out.write("label", half, values_for<std::int8_t>(half, 1, basin_of).data());
  out.commit();
}

// Every cell, scale and attribute of a file that write_grid_file() wrote.
void expect_grid_file(const std::string& path) {
  Reader r(path);
  ASSERT_GE(r.file, 0) << path;
  EXPECT_EQ(shape_of(r.file, "final_q"), (std::vector<hsize_t>{kNq, kNgamma}));
  EXPECT_EQ(shape_of(r.file, "traj_q"), (std::vector<hsize_t>{kNq, kNgamma, kNt}));
  EXPECT_EQ(read_all<double>(r.file, "q_0", H5T_NATIVE_DOUBLE), linspace(-3.0, 3.0, kNq));
  EXPECT_EQ(read_all<double>(r.file, "gamma", H5T_NATIVE_DOUBLE), linspace(0.1, 0.5, kNgamma));
  EXPECT_EQ(read_all<double>(r.file, "t", H5T_NATIVE_DOUBLE), linspace(0.0, 1.5, kNt));

  const auto q = read_all<double>(r.file, "final_q", H5T_NATIVE_DOUBLE);
  const auto traj = read_all<double>(r.file, "traj_q", H5T_NATIVE_DOUBLE);
  const auto settle = read_all<double>(r.file, "settle_time", H5T_NATIVE_DOUBLE);
  const auto status = read_all<std::uint8_t>(r.file, "status", H5T_NATIVE_UINT8);
  const auto basin = read_all<std::int8_t>(r.file, "basin", H5T_NATIVE_INT8);
  const auto label = read_all<std::int8_t>(r.file, "label", H5T_NATIVE_INT8);
  ASSERT_EQ(q.size(), static_cast<std::size_t>(kPoints));
  ASSERT_EQ(traj.size(), static_cast<std::size_t>(kPoints * kNt));
  ASSERT_EQ(settle.size(), q.size());
  ASSERT_EQ(status.size(), q.size());
  ASSERT_EQ(basin.size(), q.size());
  ASSERT_EQ(label.size(), q.size());
  for (std::int64_t i = 0; i < kPoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(q[k], final_q(i, 0)) << "point " << i;
    EXPECT_EQ(status[k], status_of(i, 0)) << "point " << i;
    EXPECT_EQ(basin[k], basin_of(i, 0)) << "point " << i;
    for (std::int64_t j = 0; j < kNt; ++j) {
      EXPECT_EQ(traj[k * kNt + static_cast<std::size_t>(j)], traj_q(i, j)) << i << ", " << j;
    }
    if (i < kPoints / 2) {
      EXPECT_EQ(settle[k], settle_time(i, 0)) << "point " << i;
      EXPECT_EQ(label[k], basin_of(i, 0)) << "point " << i;
    } else {  // never written: the fill values
      EXPECT_TRUE(std::isnan(settle[k])) << "point " << i;
      EXPECT_EQ(label[k], -128) << "point " << i;
    }
  }

  for (const char* name : {"final_q", "settle_time", "status", "basin", "label"}) {
    expect_scales(r.file, name, {"q_0", "gamma"});
  }
  expect_scales(r.file, "traj_q", {"q_0", "gamma", "t"});

  const hid_t root = H5Gopen2(r.file, "/", H5P_DEFAULT);
  EXPECT_EQ(text_attribute(root, "title"), "OutputFile test");
  EXPECT_EQ(text_attribute(root, "empty"), "");
  EXPECT_EQ(text_attribute(root, "x"), "1");
  EXPECT_EQ(attribute_values<double>(root, "h", H5T_NATIVE_DOUBLE), std::vector<double>{0.01});
  H5Gclose(root);

  const hid_t t = H5Dopen2(r.file, "t", H5P_DEFAULT);
  EXPECT_EQ(text_attribute(t, "long_name"), "time");
  EXPECT_EQ(text_attribute(t, "units"), "1");
  H5Dclose(t);
  const hid_t q0 = H5Dopen2(r.file, "q_0", H5P_DEFAULT);
  EXPECT_EQ(H5Aexists(q0, "units"), 0) << "empty units are omitted";
  H5Dclose(q0);

  const hid_t st = H5Dopen2(r.file, "status", H5P_DEFAULT);
  EXPECT_EQ(text_attribute(st, "long_name"), "integration status");
  EXPECT_TRUE(attribute_has_type(st, "flag_values", H5T_STD_U8LE, 3));
  EXPECT_EQ(attribute_values<std::uint8_t>(st, "flag_values", H5T_NATIVE_UINT8),
            (std::vector<std::uint8_t>{0, 1, 2}));
  EXPECT_EQ(text_attribute(st, "flag_meanings"), "ok diverged breakdown");
  EXPECT_EQ(H5Aexists(st, "_FillValue"), 0);
  H5Dclose(st);

  const hid_t la = H5Dopen2(r.file, "label", H5P_DEFAULT);
  EXPECT_TRUE(attribute_has_type(la, "flag_values", H5T_STD_I8LE, 2));
  EXPECT_TRUE(attribute_has_type(la, "_FillValue", H5T_STD_I8LE, 1));
  EXPECT_EQ(attribute_values<std::int8_t>(la, "_FillValue", H5T_NATIVE_INT8),
            std::vector<std::int8_t>{-128});
  H5Dclose(la);
}

// The writer goes box by box, from memory spaces of each box's shape: every cell must land.
// The file is kept for test_xarray_open.py.
TEST(OutputFile, TwoAxisRaggedRangesRoundTrip) {
  const std::string path = output_path();
  remove_both(path);
  write_grid_file(path);
  EXPECT_EQ(open_hdf5_objects(), 0);
  EXPECT_TRUE(exists(path));
  EXPECT_FALSE(exists(path + ".partial"));
  expect_grid_file(path);
}

// Three axes and several distributions in one file: the flat-range-to-hyperslab decomposition
// meets partial and whole rows at every level (the gappy distributions leave holes, where ragged
// blocks merge into one range). expect_three_axes_file() checks it.
constexpr std::int64_t kPts = 3 * 4 * 5;
constexpr std::int64_t kT = 3;
constexpr int kMaxGap = 12;
double three_axes_value(std::int64_t i, std::int64_t j) {
  return 10.0 * static_cast<double>(i) + j;
}

std::vector<std::string> three_axes_names() {
  std::vector<std::string> names = {"ragged7", "ragged13", "whole", "empty"};
  for (int m = 1; m <= kMaxGap; ++m) names.push_back("gappy" + std::to_string(m));
  return names;
}

void write_three_axes_file(const std::string& path) {
  FileLayout layout;
  layout.axes = {{"a", linspace(0, 1, 3), "a", ""},
                 {"b", linspace(0, 1, 4), "b", ""},
                 {"c", linspace(0, 1, 5), "c", ""}};
  layout.time = CoordinateSpec{"t", linspace(0, 1, kT), "time", ""};
  const std::vector<std::string> names = three_axes_names();
  std::vector<std::vector<PointRange>> distributions = {
      ragged_ranges(kPts, 7), ragged_ranges(kPts, 13), {{0, kPts}}, {}};
  for (int m = 1; m <= kMaxGap; ++m) distributions.push_back(gappy_ranges(kPts, m));
  for (const std::string& name : names) {
    layout.datasets.push_back(measure(name, name, /*time=*/true));
  }
  OutputFile out(path, layout);
  for (std::size_t d = 0; d < names.size(); ++d) {
    out.write(names[d], distributions[d],
              values_for<double>(distributions[d], kT, three_axes_value).data());
  }
  out.commit();
}

void expect_three_axes_file(const std::string& path) {
  Reader r(path);
  ASSERT_GE(r.file, 0);
  for (const std::string& name : three_axes_names()) {
    const auto values = read_all<double>(r.file, name, H5T_NATIVE_DOUBLE);
    ASSERT_EQ(values.size(), static_cast<std::size_t>(kPts * kT)) << name;
    const int gap = name.starts_with("gappy") ? std::stoi(name.substr(5)) : 0;
    for (std::int64_t i = 0; i < kPts * kT; ++i) {
      const double v = values[static_cast<std::size_t>(i)];
      const bool written = name == "empty" ? false : gap == 0 || written_in_gappy(i / kT, gap);
      if (written) {
        EXPECT_EQ(v, three_axes_value(i / kT, i % kT)) << name << " element " << i;
      } else {
        EXPECT_TRUE(std::isnan(v)) << name << " element " << i;
      }
    }
    expect_scales(r.file, name, {"a", "b", "c", "t"});
  }
}

TEST(OutputFile, ThreeAxesEveryDistribution) {
  const std::string path = sibling_path("3axes");
  std::filesystem::remove(path);
  write_three_axes_file(path);
  EXPECT_EQ(open_hdf5_objects(), 0);
  expect_three_axes_file(path);
  std::filesystem::remove(path);
}

// No grid: one trajectory, scalar datasets and time series of shape (t). The file is kept for
// test_xarray_open.py.
FileLayout scalar_layout() {
  FileLayout layout;
  layout.time = CoordinateSpec{"t", linspace(0.0, 5.0, 6), "time", ""};
  layout.datasets = {
      measure("final_q", "q at t_end"),
      flags("status", ElementType::uint8, "integration status", {0, 1, 2}, "ok diverged breakdown"),
      measure("traj_q", "q along the trajectory", /*time=*/true),
      measure("final_p", "never written"),
  };
  layout.text_attributes = {{"title", "single trajectory"}};
  return layout;
}

TEST(OutputFile, ScalarLayout) {
  const std::string path = sibling_path("scalar");
  remove_both(path);
  const std::vector<PointRange> mine = {{0, 1}};
  const double q = 0.75;
  const std::uint8_t status = 1;
  const std::vector<double> traj = {0, 1, 2, 3, 4, 5};
  {
    OutputFile out(path, scalar_layout());
    out.write("final_q", mine, &q);
    out.write("status", mine, &status);
    out.write("traj_q", mine, traj.data());
    out.write("final_p", {}, nullptr);
    out.commit();
  }
  EXPECT_EQ(open_hdf5_objects(), 0);
  Reader r(path);
  ASSERT_GE(r.file, 0);
  EXPECT_TRUE(shape_of(r.file, "final_q").empty());
  EXPECT_EQ(shape_of(r.file, "traj_q"), std::vector<hsize_t>{6});
  EXPECT_EQ(read_all<double>(r.file, "final_q", H5T_NATIVE_DOUBLE), std::vector<double>{q});
  EXPECT_EQ(read_all<std::uint8_t>(r.file, "status", H5T_NATIVE_UINT8),
            std::vector<std::uint8_t>{status});
  EXPECT_EQ(read_all<double>(r.file, "traj_q", H5T_NATIVE_DOUBLE), traj);
  const auto p = read_all<double>(r.file, "final_p", H5T_NATIVE_DOUBLE);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_TRUE(std::isnan(p[0]));
  expect_scales(r.file, "traj_q", {"t"});
}

TEST(OutputFile, UncommittedLeavesNoFile) {
  const std::string path = sibling_path("uncommitted");
  remove_both(path);
  {
    const std::vector<PointRange> mine = {{0, kPoints}};
    OutputFile out(path, grid_layout());
    out.write("final_q", mine, values_for<double>(mine, 1, final_q).data());
    EXPECT_TRUE(exists(path + ".partial"));
    EXPECT_FALSE(exists(path));
  }
  EXPECT_FALSE(exists(path + ".partial"));
  EXPECT_FALSE(exists(path));
  EXPECT_EQ(open_hdf5_objects(), 0);
}

TEST(OutputFile, StaleTemporaryIsReplaced) {
  const std::string path = sibling_path("stale");
  remove_both(path);
  std::ofstream(path + ".partial") << "left behind by a killed run";
  write_grid_file(path);
  EXPECT_FALSE(exists(path + ".partial"));
  Reader r(path);
  ASSERT_GE(r.file, 0);
  EXPECT_EQ(read_all<double>(r.file, "final_q", H5T_NATIVE_DOUBLE).size(),
            static_cast<std::size_t>(kPoints));
  std::filesystem::remove(path);
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Another program's file renamed over the temporary while this one writes (a second run of the
// same output, say): commit() puts nothing in place and names why, and neither commit() nor the
// destructor removes that file, which is not this run's.
TEST(OutputFile, ATemporarySwappedMidRunIsNeverPutInPlace) {
  const std::string path = sibling_path("swapped");
  remove_both(path);
  const std::string other = path + ".other";
  std::ofstream(other) << "another run's file";
  {
    const std::vector<PointRange> mine = {{0, kPoints}};
    OutputFile out(path, grid_layout());
    out.write("final_q", mine, values_for<double>(mine, 1, final_q).data());
    std::filesystem::rename(other, path + ".partial");  // replaces the name, not our open file
    try {
      out.commit();
      ADD_FAILURE() << "commit put a file it did not write in place";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("removed or replaced by another program"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_FALSE(exists(path));
  EXPECT_EQ(file_bytes(path + ".partial"), "another run's file");
  EXPECT_EQ(open_hdf5_objects(), 0);
  std::filesystem::remove(path + ".partial");
}


// No timestamps or other run-dependent bytes: reruns can be compared with cmp. HDF5 timestamps
// have one-second resolution, hence the pause.
TEST(OutputFile, IdenticalRunsGiveIdenticalBytes) {
  const std::string first = sibling_path("same1");
  const std::string second = sibling_path("same2");
  remove_both(first);
  remove_both(second);
  write_grid_file(first);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  write_grid_file(second);
  const std::string a = file_bytes(first);
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == file_bytes(second)) << first << " and " << second << " differ";
  std::filesystem::remove(first);
  std::filesystem::remove(second);
}

// A bad request throws, and the file stays usable.
TEST(OutputFile, BadRequestsThrowAndLeaveTheFileUsable) {
  const std::string path = sibling_path("bad_requests");
  remove_both(path);
  const std::vector<PointRange> mine = {{0, kPoints}};
  const std::vector<double> values = values_for<double>(mine, 1, final_q);
  {
    OutputFile out(path, grid_layout());
    EXPECT_THROW(out.write("no_such_dataset", mine, values.data()), std::runtime_error);
    const std::vector<PointRange> bad = {{0, kPoints + 1}};
    EXPECT_THROW(out.write("final_q", bad, values.data()), std::runtime_error);
    const std::vector<PointRange> unsorted = {{4, 6}, {0, 2}};
    EXPECT_THROW(out.write("final_q", unsorted, values.data()), std::runtime_error);
    out.write("final_q", mine, values.data());
    out.commit();
    EXPECT_THROW(out.commit(), std::runtime_error);
  }
  EXPECT_EQ(open_hdf5_objects(), 0);
  Reader r(path);
  ASSERT_GE(r.file, 0);
  EXPECT_EQ(read_all<double>(r.file, "final_q", H5T_NATIVE_DOUBLE)[kPoints - 1],
            final_q(kPoints - 1, 0));
  std::filesystem::remove(path);
}

TEST(OutputFile, CreationFailureNamesThePath) {
  const std::string path = "/nonexistent-contactsweep-dir/out.h5";
  try {
    OutputFile out(path, grid_layout());
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_EQ(open_hdf5_objects(), 0);
}

TEST(OutputFile, InvalidLayoutsAreRejected) {
  const std::string path = sibling_path("invalid");
  remove_both(path);
  FileLayout no_time = grid_layout();
  no_time.time.reset();
  EXPECT_THROW(OutputFile(path, no_time), std::runtime_error);
  FileLayout twice = grid_layout();
  twice.datasets.push_back(twice.datasets.front());
  EXPECT_THROW(OutputFile(path, twice), std::runtime_error);
  FileLayout clash = grid_layout();
  clash.datasets.front().name = "gamma";
  EXPECT_THROW(OutputFile(path, clash), std::runtime_error);
  FileLayout wide_flag = grid_layout();
  wide_flag.datasets[3].flag_values.push_back(300);  // status is uint8
  EXPECT_THROW(OutputFile(path, wide_flag), std::runtime_error);
  FileLayout empty_axis = grid_layout();
  empty_axis.axes[1].values = std::vector<double>{};
  EXPECT_THROW(OutputFile(path, empty_axis), std::runtime_error);
  EXPECT_FALSE(exists(path));
  EXPECT_FALSE(exists(path + ".partial"));
  EXPECT_EQ(open_hdf5_objects(), 0);
}

// HDF5 itself refuses the last dataset, after the file and the others exist: the constructor
// cleans up (no destructor runs for it) and says which path and which dataset failed.
TEST(OutputFile, FailureDuringCreationCleansUp) {
  const std::string path = sibling_path("bad_name");
  remove_both(path);
  FileLayout layout = grid_layout();
  layout.datasets.back().name = ".";
  try {
    OutputFile out(path, layout);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path + ".partial"), std::string::npos) << message;
    EXPECT_NE(message.find("dataset '.'"), std::string::npos) << message;
  }
  EXPECT_FALSE(exists(path + ".partial"));
  EXPECT_FALSE(exists(path));
  EXPECT_EQ(open_hdf5_objects(), 0);
}

}  // namespace
