// Putting the finished file in place, durably, and room for it before it is written.
#include "io/durable_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace cs {
namespace {

void sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + path + ": " + std::strerror(errno));
  const int status = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // Some file systems cannot sync a directory (EINVAL): the rename is then as durable as it gets.
  if (status != 0 && !(error == EINVAL && (flags & O_DIRECTORY)))
    throw std::runtime_error("cannot sync " + path + ": " + std::strerror(error));
}

std::string fmt_bytes(double bytes) {
  return std::to_string(static_cast<long long>(bytes / (1024.0 * 1024.0))) + " MiB";
}

}  // namespace

void place_durably(const std::string& partial_path, const std::string& final_path, bool replace) {
  sync_path(partial_path, O_RDONLY | O_NOFOLLOW);
  if (replace) {
    std::filesystem::rename(partial_path, final_path);
  } else if (::link(partial_path.c_str(), final_path.c_str()) == 0) {
    std::filesystem::remove(partial_path);
  } else if (errno == EEXIST) {
    throw std::runtime_error(
        "'" + final_path + "' appeared while this run was computing (made by another program); "
        "it was not replaced. Every finished block is kept in the journal: move that file away "
        "and run again with --resume");
  } else if (errno == EPERM || errno == EOPNOTSUPP || errno == EXDEV || errno == EMLINK) {
    // A file system without hard links: check, then rename (a window of a few microseconds).
    if (std::filesystem::exists(final_path))
      throw std::runtime_error("'" + final_path + "' appeared while this run was computing; it "
                               "was not replaced: move it away and run again with --resume");
    std::filesystem::rename(partial_path, final_path);
  } else {
    throw std::runtime_error("cannot link " + partial_path + " to " + final_path + ": " +
                             std::strerror(errno));
  }
  sync_directory(std::filesystem::absolute(final_path).parent_path().string());
}

void sync_directory(const std::string& path) { sync_path(path, O_RDONLY | O_DIRECTORY); }

void check_room_for(const std::string& path, double bytes) {
  // O_EXCL: never through a link someone planted under the temporary's name (a shared
  // directory), never into a file that is not ours.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
  const int error = ::posix_fallocate(fd, 0, static_cast<off_t>(bytes));
  ::close(fd);
  ::unlink(path.c_str());
  if (error == ENOSPC || error == EDQUOT)
    throw std::runtime_error(fmt_bytes(bytes) + " for the output do not fit on its disk: " +
                             std::strerror(error));
  // EOPNOTSUPP, EINVAL: a file system that cannot reserve; the earlier free-space check stands.
}

}  // namespace cs
