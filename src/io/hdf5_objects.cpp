// HDF5 identifiers, errors, element types and attributes for the result file (output_file.cpp).
#include "io/hdf5_objects.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace cs::hdf5 {
namespace {

// HDF5's own printing is switched off (OutputFile's constructor); on failure we pull the
// innermost message (usually the root cause, e.g. "No such file or directory") out of the
// error stack.
herr_t remember_innermost(unsigned, const H5E_error2_t* error, void* out) {
  if (error->desc != nullptr && *error->desc != '\0') {
    *static_cast<std::string*>(out) = error->desc;
  }
  return 0;
}

}  // namespace

std::string hdf5_error_detail() {
  std::string detail;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, remember_innermost, &detail);
  H5Eclear2(H5E_DEFAULT);
  return detail;
}

[[noreturn]] void fail(const std::string& path, const std::string& what, std::string detail) {
  std::string message = path + ": " + what;
  if (!detail.empty()) message += " (" + detail + ")";
  throw std::runtime_error(message);
}

hid_t memory_type(ElementType type) {
  switch (type) {
    case ElementType::int8: return H5T_NATIVE_INT8;
    case ElementType::uint8: return H5T_NATIVE_UINT8;
    case ElementType::int16: return H5T_NATIVE_INT16;
    case ElementType::int32: return H5T_NATIVE_INT32;
    case ElementType::float64: break;
  }
  return H5T_NATIVE_DOUBLE;
}

hid_t file_type(ElementType type) {
  switch (type) {
    case ElementType::int8: return H5T_STD_I8LE;
    case ElementType::uint8: return H5T_STD_U8LE;
    case ElementType::int16: return H5T_STD_I16LE;
    case ElementType::int32: return H5T_STD_I32LE;
    case ElementType::float64: break;
  }
  return H5T_IEEE_F64LE;
}

bool representable(double value, ElementType type) {
  switch (type) {
    case ElementType::int8: return value == std::trunc(value) && value >= -128 && value <= 127;
    case ElementType::uint8: return value == std::trunc(value) && value >= 0 && value <= 255;
    case ElementType::int16:
      return value == std::trunc(value) && value >= -32768 && value <= 32767;
    case ElementType::int32:
      return value == std::trunc(value) && value >= -2147483648.0 && value <= 2147483647.0;
    case ElementType::float64: break;
  }
  return true;
}

TypedValue typed(double value, ElementType type) {
  TypedValue v;
  v.d = value;
  if (type != ElementType::float64 && !std::isnan(value)) {
    if (representable(value, ElementType::int8)) v.i8 = static_cast<std::int8_t>(value);
    if (representable(value, ElementType::uint8)) v.u8 = static_cast<std::uint8_t>(value);
    if (representable(value, ElementType::int16)) v.i16 = static_cast<std::int16_t>(value);
    if (representable(value, ElementType::int32)) v.i32 = static_cast<std::int32_t>(value);
  }
  return v;
}

std::size_t element_size(ElementType type) {
  switch (type) {
    case ElementType::int8:
    case ElementType::uint8: return 1;
    case ElementType::int16: return 2;
    case ElementType::int32: return 4;
    case ElementType::float64: break;
  }
  return 8;
}

void write_attribute(hid_t object, const std::string& name, hid_t file_t, hid_t mem_t, hid_t space,
                     const void* value, const Checker& check) {
  const std::string what = "cannot write attribute '" + name + "'";
  AttributeHandle attribute(
      check(H5Acreate2(object, name.c_str(), file_t, space, H5P_DEFAULT, H5P_DEFAULT), what));
  check(H5Awrite(attribute.get(), mem_t, value), what);
  check.require(attribute.close(), what);
}

void write_text_attribute(hid_t object, const std::string& name, const std::string& value,
                          const Checker& check) {
  const std::string what = "cannot write attribute '" + name + "'";
  TypeHandle type(check(H5Tcopy(H5T_C_S1), what));
  check(H5Tset_size(type.get(), H5T_VARIABLE), what);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), what);
  SpaceHandle space(check(H5Screate(H5S_SCALAR), what));
  const char* text = value.c_str();
  write_attribute(object, name, type.get(), type.get(), space.get(), &text, check);
}

void write_number_attribute(hid_t object, const std::string& name, double value,
                            const Checker& check) {
  SpaceHandle space(check(H5Screate(H5S_SCALAR), "cannot write attribute '" + name + "'"));
  write_attribute(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space.get(), &value, check);
}

void write_typed_attribute(hid_t object, const std::string& name, double value, ElementType type,
                           const Checker& check) {
  SpaceHandle space(check(H5Screate(H5S_SCALAR), "cannot write attribute '" + name + "'"));
  const TypedValue v = typed(value, type);
  write_attribute(object, name, file_type(type), memory_type(type), space.get(), v.pointer(type),
                  check);
}

// 1-D array of the dataset's own type (CF: flag_values has the variable's type).
namespace {

// 1-D array of the dataset's own type (CF: flag_values has the variable's type).
template <typename T>
void write_flag_values_as(hid_t object, const std::vector<int>& values, ElementType type,
                          const Checker& check) {
  const std::vector<T> converted(values.begin(), values.end());  // validate() checked the range
  const hsize_t n = converted.size();
  SpaceHandle space(check(H5Screate_simple(1, &n, nullptr), "cannot write 'flag_values'"));
  write_attribute(object, "flag_values", file_type(type), memory_type(type), space.get(),
                  converted.data(), check);
}

}  // namespace

void write_flag_values(hid_t object, const std::vector<int>& values, ElementType type,
                       const Checker& check) {
  switch (type) {
    case ElementType::int8: return write_flag_values_as<std::int8_t>(object, values, type, check);
    case ElementType::uint8: return write_flag_values_as<std::uint8_t>(object, values, type, check);
    case ElementType::int16: return write_flag_values_as<std::int16_t>(object, values, type, check);
    case ElementType::int32: return write_flag_values_as<std::int32_t>(object, values, type, check);
    case ElementType::float64: break;
  }
  write_flag_values_as<double>(object, values, type, check);
}

void write_descriptive_attributes(hid_t object, const std::string& long_name,
                                  const std::string& units, const Checker& check) {
  if (!long_name.empty()) write_text_attribute(object, "long_name", long_name, check);
  if (!units.empty()) write_text_attribute(object, "units", units, check);
}

}  // namespace cs::hdf5
