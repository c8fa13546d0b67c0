// What the result file's writer (output_file.cpp) needs from HDF5, in small pieces: owners of
// HDF5 identifiers, errors as exceptions that name the file, element types, attributes.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/output_file.hpp"

namespace cs::hdf5 {

// Small RAII owners of HDF5 identifiers: one per kind, each calls its own H5*close.

template <herr_t (*Close)(hid_t)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      close();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { close(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes now and reports whether HDF5 accepted it (the destructor cannot report).
  // Never retried: HDF5 may have freed part of an object whose close failed.
  bool close() {
    if (!valid()) return true;
    const herr_t status = Close(std::exchange(id_, H5I_INVALID_HID));
    return status >= 0;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

using FileHandle = Handle<H5Fclose>;
using DatasetHandle = Handle<H5Dclose>;
using SpaceHandle = Handle<H5Sclose>;
using TypeHandle = Handle<H5Tclose>;
using PropertyHandle = Handle<H5Pclose>;
using AttributeHandle = Handle<H5Aclose>;

// ---------------------------------------------------------------------------------------------
// Errors

// HDF5's innermost message on its error stack (usually the root cause, e.g. "No such file or
// directory"), and clears the stack.
std::string hdf5_error_detail();

// Throws std::runtime_error "path: what (detail)".
[[noreturn]] void fail(const std::string& path, const std::string& what, std::string detail = {});

// Checks the result of an HDF5 call: a failure throws, naming the file, the step and HDF5's
// innermost message.
class Checker {
 public:
  Checker() = default;
  explicit Checker(std::string path) : path_(std::move(path)) {}
  // HDF5 identifiers and herr_t are both negative on failure.
  template <typename T>
  T operator()(T result, const std::string& what) const {
    if (result < 0) fail(path_, what, hdf5_error_detail());
    return result;
  }
  // For HDF5 calls that report through a bool (Handle::close).
  void require(bool ok, const std::string& what) const { (*this)(ok ? 0 : -1, what); }

 private:
  std::string path_;
};

// ---------------------------------------------------------------------------------------------
// Element types

hid_t memory_type(ElementType type);
// Fixed little-endian file types, so the file is the same whatever machine wrote it.
hid_t file_type(ElementType type);
std::size_t element_size(ElementType type);

// One value converted to a dataset's element type, as raw bytes for H5Pset_fill_value/H5Awrite.
struct TypedValue {
  double d = 0;
  std::int8_t i8 = 0;
  std::uint8_t u8 = 0;
  std::int16_t i16 = 0;
  std::int32_t i32 = 0;
  const void* pointer(ElementType type) const {
    switch (type) {
      case ElementType::int8: return &i8;
      case ElementType::uint8: return &u8;
      case ElementType::int16: return &i16;
      case ElementType::int32: return &i32;
      case ElementType::float64: break;
    }
    return &d;
  }
};

// Integer labels must be exactly representable; a silently wrapped flag value would mislabel data.
bool representable(double value, ElementType type);
TypedValue typed(double value, ElementType type);

// ---------------------------------------------------------------------------------------------
// Attributes. Strings are scalar, variable-length UTF-8: h5py (hence h5netcdf and xarray) returns
// them as Python str whatever their length, whereas fixed-length strings of length one come back
// as bytes.

void write_attribute(hid_t object, const std::string& name, hid_t file_t, hid_t mem_t, hid_t space,
                     const void* value, const Checker& check);
void write_text_attribute(hid_t object, const std::string& name, const std::string& value,
                          const Checker& check);
void write_number_attribute(hid_t object, const std::string& name, double value,
                            const Checker& check);
// Scalar of the dataset's own type: CF wants _FillValue to match the variable exactly.
void write_typed_attribute(hid_t object, const std::string& name, double value, ElementType type,
                           const Checker& check);
// 1-D array of the dataset's own type (CF: flag_values has the variable's type).
void write_flag_values(hid_t object, const std::vector<int>& values, ElementType type,
                       const Checker& check);
// long_name and units, each omitted when empty.
void write_descriptive_attributes(hid_t object, const std::string& long_name,
                                  const std::string& units, const Checker& check);

}  // namespace cs::hdf5
