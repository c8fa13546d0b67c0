// A kernel library in the cache is loaded only once it is proven whole and made for its key: a
// trailer appended after linking (magic, key, the size of what precedes it and its checksum;
// ELF ignores bytes past its sections), checked on the descriptor that dlopen then maps, so
// neither a truncated file (SIGBUS inside dlopen) nor another K's kernel under this name is
// ever loaded.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <string>

#include "io/owned_directory.hpp"

namespace cs {

// A kernel's key (kernel_cache.cpp): 128 bits of SHA-256, in hexadecimal digits.
inline constexpr std::size_t kKernelKeyDigits = 32;

std::string library_name(const std::string& key);  // kernel-KEY.so

// A cached library of ours, read and checked, with its descriptor open for dlopen.
struct CheckedLibrary {
  int fd = -1;
  bool missing = false;
  std::string problem;  // "" when fit to load
  CheckedLibrary() = default;
  CheckedLibrary(const CheckedLibrary&) = delete;
  CheckedLibrary& operator=(const CheckedLibrary&) = delete;
  ~CheckedLibrary() {
    if (fd >= 0) ::close(fd);
  }
};

// Opens `name` in `dir` without following a link and checks it: a regular file of this user's,
// writable by nobody else, whose trailer is whole and names `key`.
void check_library(const OwnedDirectory& dir, const std::string& name, const std::string& key,
                   CheckedLibrary& out);

// Appends the trailer to the freshly linked library `name` in `dir` (mode 0600, fsynced).
void seal_library(const OwnedDirectory& dir, const std::string& name, const std::string& key);

}  // namespace cs
