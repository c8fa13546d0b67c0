// OutputFile created DatasetsFirst (a streamed run: parallel/block_stream.hpp) and completed at
// the end: the file must be the one a one-step OutputFile writes, objects in the same creation
// order, and a dataset whose description changed at the end (`basin`: numbered labels, or
// labels past int8) must come out with its final type, attributes and dimension scales.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/output_file.hpp"
#include "support/hdf5_reading.hpp"
#include "support/private_temp_dir.hpp"

namespace {

using cs::CoordinateSpec;
using cs::DatasetSpec;
using cs::ElementType;
using cs::FileLayout;
using cs::OutputFile;
using cs::PointRange;
using cs::test::expect_scales;
using cs::test::PrivateTempDir;
using cs::test::read_all;
using cs::test::Reader;
using cs::test::text_attribute;

constexpr std::int64_t kPoints = 12;  // 4 × 3

DatasetSpec basin_by_rule() {
  return {"basin", ElementType::int8, false, "basin of attraction", "", {-1, 0, 1},
          "left undecided right", std::nullopt};
}

// The layout before the run: the per-point datasets, `basin` as the plan describes it.
FileLayout early_layout() {
  FileLayout layout;
  layout.axes = {{"x", {0, 1, 2, 3}, "x", ""}, {"y", {0, 1, 2}, "y", ""}};
  layout.datasets = {{"status", ElementType::uint8, false, "integration status", "", {}, "",
                      std::nullopt, 5.0},
                     basin_by_rule(),
                     {"settle_time", ElementType::float64, false, "settle time", "time", {}, "",
                      std::nullopt}};
  layout.text_attributes = {{"title", "completion"}};
  layout.number_attributes = {{"mpi_ranks", 2.0}};
  return layout;
}

// The whole layout, known at the end: `basin` as given, the attractor table, statistics.
FileLayout whole_layout(const DatasetSpec& basin) {
  FileLayout layout = early_layout();
  layout.datasets[1] = basin;
  layout.extra_dimensions = {{"attractor", {1, 2}, "label of the attractor", ""}};
  layout.tables = {{{"attractor_cells", ElementType::float64, false, "cells", "", {}, "",
                     std::nullopt},
                    {"attractor"},
                    {5, 7}}};
  layout.text_attributes["wada"] = "no";
  layout.number_attributes["basin_entropy"] = 0.25;
  return layout;
}

std::vector<std::string> names_in_creation_order(hid_t file) {
  std::vector<std::string> names;
  H5Literate(
      file, H5_INDEX_CRT_ORDER, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* out) -> herr_t {
        static_cast<std::vector<std::string>*>(out)->push_back(name);
        return 0;
      },
      &names);
  return names;
}

const std::vector<double> kStatus = {0, 1, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0};
const std::vector<double> kSettle = {1.5, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12.25};

// Streamed: status and settle_time in two blocks, out of order, before complete(); basin after.
template <typename Label>
void write_streamed(const std::string& path, const DatasetSpec& basin,
                    const std::vector<Label>& labels) {
  OutputFile out(path, early_layout(), OutputFile::DatasetsFirst{});
  const std::vector<std::uint8_t> status(kStatus.begin(), kStatus.end());
  out.write("status", {{6, 12}}, status.data() + 6);
  out.write("settle_time", {{6, 12}}, kSettle.data() + 6);
  out.write("status", {{0, 6}}, status.data());
  out.write("settle_time", {{0, 6}}, kSettle.data());
  EXPECT_THROW(out.commit(), std::runtime_error);  // not complete yet
  out.complete(whole_layout(basin));
  out.write("basin", {{0, kPoints}}, labels.data());
  out.commit();
}

void expect_streamed_values(hid_t file) {
  const auto status = read_all<std::uint8_t>(file, "status", H5T_NATIVE_UINT8);
  EXPECT_EQ(std::vector<double>(status.begin(), status.end()), kStatus);
  EXPECT_EQ(read_all<double>(file, "settle_time", H5T_NATIVE_DOUBLE), kSettle);
  EXPECT_EQ(read_all<double>(file, "attractor_cells", H5T_NATIVE_DOUBLE),
            (std::vector<double>{5, 7}));
  EXPECT_EQ(text_attribute(file, "wada"), "no");
  EXPECT_EQ(text_attribute(file, "title"), "completion");
  expect_scales(file, "basin", {"x", "y"});
  expect_scales(file, "settle_time", {"x", "y"});
}

// `path` holds the streamed values, and the objects of `reference` in the same creation order.
void expect_same_objects(const std::string& path, const std::string& reference) {
  Reader a(path), b(reference);
  ASSERT_GE(a.file, 0);
  ASSERT_GE(b.file, 0);
  EXPECT_EQ(names_in_creation_order(a.file), names_in_creation_order(b.file));
  expect_streamed_values(a.file);
}

TEST(OutputCompletion, SameDescriptionGivesTheOneStepFile) {
  const PrivateTempDir dir("contactsweep_completion_");  // removed last, with its files
  const std::string streamed = dir.file("streamed.h5"), whole = dir.file("whole.h5");
  const std::vector<std::int8_t> labels = {-1, 1, 1, 0, -1, -1, 1, 1, 1, 1, -1, 0};
  write_streamed(streamed, basin_by_rule(), labels);
  {
    OutputFile out(whole, whole_layout(basin_by_rule()));
    const std::vector<std::uint8_t> status(kStatus.begin(), kStatus.end());
    out.write("status", {{0, kPoints}}, status.data());
    out.write("settle_time", {{0, kPoints}}, kSettle.data());
    out.write("basin", {{0, kPoints}}, labels.data());
    out.commit();
  }
  expect_same_objects(streamed, whole);
  Reader a(streamed);
  ASSERT_GE(a.file, 0);
  EXPECT_EQ(read_all<std::int8_t>(a.file, "basin", H5T_NATIVE_INT8), labels);
  const hid_t basin = H5Dopen2(a.file, "basin", H5P_DEFAULT);
  EXPECT_EQ(text_attribute(basin, "long_name"), "basin of attraction");
  EXPECT_EQ(text_attribute(basin, "flag_meanings"), "left undecided right");
  H5Dclose(basin);
}

TEST(OutputCompletion, NumberedLabelsLoseTheRulesFlags) {
  const PrivateTempDir dir("contactsweep_completion_");
  const std::string path = dir.file("numbered.h5");
  const DatasetSpec numbered{"basin", ElementType::int8, false, "numbered basins", "", {}, "",
                             std::nullopt};
  const std::vector<std::int8_t> labels = {1, 2, 2, 0, 1, 1, 2, 2, 2, 2, 1, 0};
  write_streamed(path, numbered, labels);
  Reader r(path);
  ASSERT_GE(r.file, 0);
  expect_streamed_values(r.file);
  EXPECT_EQ(read_all<std::int8_t>(r.file, "basin", H5T_NATIVE_INT8), labels);
  const hid_t basin = H5Dopen2(r.file, "basin", H5P_DEFAULT);
  EXPECT_EQ(text_attribute(basin, "long_name"), "numbered basins");
  EXPECT_EQ(H5Aexists(basin, "flag_values"), 0);
  EXPECT_EQ(H5Aexists(basin, "flag_meanings"), 0);
  H5Dclose(basin);
}

TEST(OutputCompletion, LabelsPastInt8AreWrittenAsInt16) {
  const PrivateTempDir dir("contactsweep_completion_");
  const std::string path = dir.file("int16.h5");
  const DatasetSpec wide{"basin", ElementType::int16, false, "numbered basins", "", {}, "",
                         std::nullopt};
  const std::vector<std::int16_t> labels = {1, 300, 2, 0, 1, 1, 2, 2, 2, 2, 1, -200};
  write_streamed(path, wide, labels);
  Reader r(path);
  ASSERT_GE(r.file, 0);
  expect_streamed_values(r.file);
  EXPECT_EQ(read_all<std::int16_t>(r.file, "basin", H5T_NATIVE_INT16), labels);
  const hid_t basin = H5Dopen2(r.file, "basin", H5P_DEFAULT);
  const hid_t type = H5Dget_type(basin);
  EXPECT_EQ(H5Tget_size(type), 2u);
  H5Tclose(type);
  EXPECT_EQ(H5Aexists(basin, "flag_values"), 0);
  H5Dclose(basin);
}

// A run's order (output_assembly.cpp): `basin` redefined and written first, read back as int32
// for the statistics (any range, rows cut anywhere), then the tables and attributes: the same
// objects in the same creation order as completing first, and the same values.
TEST(OutputCompletion, BasinWrittenFirstIsReadBackAndGivesTheSameFile) {
  const PrivateTempDir dir("contactsweep_completion_");
  const std::string first = dir.file("basin_first.h5"), usual = dir.file("basin_usual.h5");
  const DatasetSpec wide{"basin", ElementType::int16, false, "numbered basins", "", {}, "",
                         std::nullopt};
  const std::vector<std::int16_t> labels = {1, 300, 2, 0, 1, 1, 2, 2, 2, 2, 1, -200};
  write_streamed(usual, wide, labels);
  {
    OutputFile out(first, early_layout(), OutputFile::DatasetsFirst{});
    const std::vector<std::uint8_t> status(kStatus.begin(), kStatus.end());
    out.write("status", {{0, kPoints}}, status.data());
    out.write("settle_time", {{0, kPoints}}, kSettle.data());
    out.complete_datasets(whole_layout(wide));
    out.write("basin", {{0, kPoints}}, labels.data());
    std::vector<std::int32_t> back(kPoints, 99);
    out.read("basin", {1, 7}, back.data() + 1);  // rows of 3: a part of one, one, a part
    out.read("basin", {7, 12}, back.data() + 7);
    out.read("basin", {0, 1}, back.data());
    EXPECT_EQ(back, std::vector<std::int32_t>(labels.begin(), labels.end()));
    EXPECT_THROW(out.read("settle_time", {0, 13}, back.data()), std::runtime_error);
    out.complete(whole_layout(wide));
    out.commit();
  }
  expect_same_objects(first, usual);
  Reader a(first);
  ASSERT_GE(a.file, 0);
  EXPECT_EQ(read_all<std::int16_t>(a.file, "basin", H5T_NATIVE_INT16), labels);
}

}  // namespace
