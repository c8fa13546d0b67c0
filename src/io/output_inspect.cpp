#include "io/output_inspect.hpp"

#include <hdf5.h>

#include <vector>

namespace cs {

std::optional<std::string> read_spec_attribute(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // a foreign file is an answer, not an error
  std::optional<std::string> result;
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return result;
  if (H5Aexists(file, "spec") > 0) {
    hid_t attr = H5Aopen(file, "spec", H5P_DEFAULT);
    hid_t type = H5Aget_type(attr);
    if (attr >= 0 && type >= 0 && H5Tget_class(type) == H5T_STRING) {
      if (H5Tis_variable_str(type) > 0) {
        char* text = nullptr;
        hid_t mem = H5Tcopy(H5T_C_S1);
        H5Tset_size(mem, H5T_VARIABLE);
        H5Tset_cset(mem, H5Tget_cset(type));
        if (H5Aread(attr, mem, &text) >= 0 && text != nullptr) {
          result = std::string(text);
          H5free_memory(text);
        }
        H5Tclose(mem);
      } else {
        std::vector<char> text(H5Tget_size(type) + 1, '\0');
        if (H5Aread(attr, type, text.data()) >= 0) result = std::string(text.data());
      }
    }
    if (type >= 0) H5Tclose(type);
    if (attr >= 0) H5Aclose(attr);
  }
  H5Fclose(file);
  return result;
}

}  // namespace cs
