#include "io/output_inspect.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include <fmt/format.h>

namespace cs {
namespace {

// The root attribute `spec` of an HDF5 file; nullopt when the file cannot be read as a
// contactsweep output. Serial HDF5, any rank.
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

}  // namespace

ExistingOutput inspect_existing_output(const std::string& path) {
  ExistingOutput out;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    struct stat link {};
    out.why_not = ::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)
                      ? "is a symbolic link"
                      : fmt::format("cannot be opened ({})", std::strerror(error));
    return out;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    out.why_not = "is not a regular file";
  } else if (st.st_uid != ::geteuid()) {
    out.why_not = fmt::format("belongs to user id {}, not to you", st.st_uid);
  } else {
    out.ours = true;
    out.spec = read_spec_attribute(fmt::format("/proc/self/fd/{}", fd));  // the file checked
  }
  ::close(fd);
  return out;
}

}  // namespace cs
