// A directory of the test's own under $TMPDIR (mkdtemp: a fresh name, mode 0700), removed with
// everything in it when the object goes out of scope. A fixed or guessable name in a shared
// /tmp could be planted in advance by another user (a link the test would then write through).
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace cs::test {

class PrivateTempDir {
 public:
  explicit PrivateTempDir(const std::string& prefix) {
    std::string name =
        (std::filesystem::temp_directory_path() / (prefix + "XXXXXX")).string();
    if (::mkdtemp(name.data()) == nullptr)
      throw std::runtime_error("mkdtemp failed for " + name);
    path_ = name;
  }
  ~PrivateTempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  PrivateTempDir(const PrivateTempDir&) = delete;
  PrivateTempDir& operator=(const PrivateTempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // A file name inside the directory.
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace cs::test
