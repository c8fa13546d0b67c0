#include "kernel_build/sealed_library.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "parallel/run_identity.hpp"

namespace cs {
namespace {

// Appended to every library after linking (ELF ignores bytes past its sections): proves the file
// is whole and was made for this key before it is mapped, so neither a truncated file (SIGBUS
// inside dlopen) nor another K's kernel under this name is ever loaded.
constexpr char kTrailerMagic[8] = {'C', 'S', 'K', 'E', 'R', 'N', '0', '2'};
constexpr std::size_t kKeyChars = kKernelKeyDigits;
constexpr std::size_t kTrailerBytes = sizeof kTrailerMagic + kKeyChars + 2 * sizeof(std::uint64_t);

// The library's trailer: magic, key, size of what precedes it, its checksum.
std::string trailer(std::string_view body, const std::string& key) {
  std::string out(kTrailerMagic, sizeof kTrailerMagic);
  out += key;
  const std::uint64_t fields[2] = {body.size(), fnv1a(body)};
  out.append(reinterpret_cast<const char*>(fields), sizeof fields);
  return out;
}

// Why `bytes` is not a whole library made for `key`; "" when it is.
std::string why_not_kernel_of(const std::string& bytes, const std::string& key) {
  if (bytes.size() < kTrailerBytes) return "it is truncated";
  const std::string_view body(bytes.data(), bytes.size() - kTrailerBytes);
  const std::string_view tail(bytes.data() + body.size(), kTrailerBytes);
  if (tail.substr(0, sizeof kTrailerMagic) != std::string_view(kTrailerMagic, sizeof kTrailerMagic))
    return "it is truncated or not a kernel of this contactsweep";
  if (tail.substr(sizeof kTrailerMagic, kKeyChars) != key)
    return "it was built for another kernel (key " +
           std::string(tail.substr(sizeof kTrailerMagic, kKeyChars)) + ")";
  if (tail != trailer(body, key)) return "it is damaged (its size or checksum differs)";
  return {};
}

}  // namespace

void check_library(const OwnedDirectory& dir, const std::string& name, const std::string& key,
                   CheckedLibrary& out) {
  out.fd = ::openat(dir.fd(), name.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (out.fd < 0) {
    out.missing = errno == ENOENT;
    out.problem = errno == ELOOP ? "it is a symbolic link" : std::strerror(errno);
    return;
  }
  struct stat status {};
  if (::fstat(out.fd, &status) != 0 || !S_ISREG(status.st_mode)) {
    out.problem = "it is not a regular file";
  } else if (status.st_uid != ::geteuid()) {
    out.problem = fmt::format("it belongs to user id {}, not to you", status.st_uid);
  } else if ((status.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
    out.problem = fmt::format("others can write to it (mode {:04o})", status.st_mode & 07777);
  } else {
    std::string bytes(static_cast<std::size_t>(status.st_size), '\0');
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::pread(out.fd, bytes.data() + done, bytes.size() - done,
                                static_cast<off_t>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    out.problem = done == bytes.size() ? why_not_kernel_of(bytes, key) : "it cannot be read";
  }
  if (!out.problem.empty()) {
    ::close(out.fd);
    out.fd = -1;
  }
}

std::string library_name(const std::string& key) { return "kernel-" + key + ".so"; }

// Appends the trailer to the freshly linked library `name` in `dir`.
void seal_library(const OwnedDirectory& dir, const std::string& name, const std::string& key) {
  std::string bytes;
  if (!dir.read_file(name, bytes))
    throw std::runtime_error("the compiler wrote no library " + dir.path_of(name));
  const std::string tail = trailer(bytes, key);
  const int fd = ::openat(dir.fd(), name.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  const bool ok = fd >= 0 && ::write(fd, tail.data(), tail.size()) == static_cast<ssize_t>(tail.size()) &&
                  ::fchmod(fd, 0600) == 0 && ::fsync(fd) == 0;
  const int error = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) throw std::runtime_error("cannot finish the library " + dir.path_of(name) + ": " +
                                    std::strerror(error));
}

}  // namespace cs
