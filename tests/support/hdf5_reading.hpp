// Reading an HDF5 file back with plain HDF5 calls, for tests that check what a writer left:
// shapes, whole datasets, attributes (string, typed) and the dimension scales attached.
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>
#include <hdf5_hl.h>

#include <algorithm>
#include <string>
#include <vector>

namespace cs::test {

struct Reader {
  hid_t file = H5I_INVALID_HID;
  explicit Reader(const std::string& path) {
    file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  }
  ~Reader() {
    if (file >= 0) H5Fclose(file);
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;
};

inline std::vector<hsize_t> shape_of(hid_t file, const std::string& name) {
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(dataset);
  std::vector<hsize_t> dims(
      static_cast<std::size_t>(std::max(0, H5Sget_simple_extent_ndims(space))));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  H5Sclose(space);
  H5Dclose(dataset);
  return dims;
}

template <typename T>
std::vector<T> read_all(hid_t file, const std::string& name, hid_t mem_type) {
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(dataset);
  std::vector<T> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  const herr_t status = H5Dread(dataset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(dataset);
  if (status < 0) out.clear();
  return out;
}

// A scalar string attribute, fixed or variable length; "<missing>" when absent.
inline std::string text_attribute(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return "<missing>";
  const hid_t attribute = H5Aopen(object, name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Aget_type(attribute);
  std::string out = "<not a string>";
  if (H5Tget_class(type) == H5T_STRING && H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    const hid_t mem = H5Tget_native_type(type, H5T_DIR_ASCEND);
    if (H5Aread(attribute, mem, &text) >= 0 && text != nullptr) {
      out = text;
      H5free_memory(text);
    }
    H5Tclose(mem);
  } else if (H5Tget_class(type) == H5T_STRING) {
    std::vector<char> text(H5Tget_size(type) + 1, '\0');
    if (H5Aread(attribute, type, text.data()) >= 0) out = text.data();
  }
  H5Tclose(type);
  H5Aclose(attribute);
  return out;
}

// True when attribute `name` of `object` has exactly file type `expected` and `count` elements.
inline bool attribute_has_type(hid_t object, const std::string& name, hid_t expected, hssize_t count) {
  if (H5Aexists(object, name.c_str()) <= 0) return false;
  const hid_t attribute = H5Aopen(object, name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Aget_type(attribute);
  const hid_t space = H5Aget_space(attribute);
  const bool ok = H5Tequal(type, expected) > 0 && H5Sget_simple_extent_npoints(space) == count;
  H5Sclose(space);
  H5Tclose(type);
  H5Aclose(attribute);
  return ok;
}

template <typename T>
std::vector<T> attribute_values(hid_t object, const std::string& name, hid_t mem_type) {
  const hid_t attribute = H5Aopen(object, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Aget_space(attribute);
  std::vector<T> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Aread(attribute, mem_type, out.data());
  H5Sclose(space);
  H5Aclose(attribute);
  return out;
}

// Names of the scales attached to each dimension of `name`, checked with H5DSis_attached.
inline void expect_scales(hid_t file, const std::string& name, const std::vector<std::string>& scales) {
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  ASSERT_GE(dataset, 0) << name;
  for (std::size_t d = 0; d < scales.size(); ++d) {
    const hid_t scale = H5Dopen2(file, scales[d].c_str(), H5P_DEFAULT);
    EXPECT_GT(H5DSis_scale(scale), 0) << scales[d];
    EXPECT_GT(H5DSis_attached(dataset, scale, static_cast<unsigned>(d)), 0)
        << scales[d] << " on dim " << d << " of " << name;
    EXPECT_EQ(H5DSget_num_scales(dataset, static_cast<unsigned>(d)), 1) << name << " dim " << d;
    H5Dclose(scale);
  }
  H5Dclose(dataset);
}

}  // namespace cs::test
