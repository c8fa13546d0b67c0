#include "io/owned_directory.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "model/run_spec.hpp"

namespace cs {
namespace {

std::string errno_text(int error) { return std::strerror(error); }

// mkdir -p, each missing component 0700: a cache's parents (~/.cache) are private too.
int make_directories(const std::string& path) {
  if (::mkdir(path.c_str(), 0700) == 0) return 0;
  if (errno == EEXIST) return 0;
  if (errno != ENOENT) return errno;
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos || slash == 0) return ENOENT;
  if (int error = make_directories(path.substr(0, slash)); error != 0) return error;
  return ::mkdir(path.c_str(), 0700) == 0 || errno == EEXIST ? 0 : errno;
}

}  // namespace

std::string why_not_owned_directory(const struct stat& status) {
  if (S_ISLNK(status.st_mode)) return "it is a symbolic link";
  if (!S_ISDIR(status.st_mode)) return "it is not a directory";
  if (status.st_uid != ::geteuid())
    return fmt::format("it belongs to user id {}, not to you ({})", status.st_uid, ::geteuid());
  if ((status.st_mode & (S_IWGRP | S_IWOTH)) != 0)
    return fmt::format("others can write to it (mode {:04o})", status.st_mode & 07777);
  return {};
}

OwnedDirectory::OwnedDirectory(const std::string& path, const std::string& purpose,
                               Create create)
    : path_(path) {
  auto refuse = [&](const std::string& why, const std::string& fix) {
    throw InputError(fmt::format("{} '{}' cannot be trusted: {}; {}", purpose, path, why, fix));
  };
  if (create == Create::yes) {
    if (::mkdir(path.c_str(), 0700) == 0) {
      created_ = true;
    } else if (errno == ENOENT) {
      if (int error = make_directories(path); error != 0)
        throw InputError(fmt::format("cannot create {} '{}': {}", purpose, path, errno_text(error)));
      created_ = true;
    } else if (errno != EEXIST) {
      throw InputError(fmt::format("cannot create {} '{}': {}", purpose, path, errno_text(errno)));
    }
  }
  fd_ = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd_ < 0) {
    const int error = errno;
    if (error == ENOENT && create == Create::no) return;
    struct stat link {};
    if (::lstat(path.c_str(), &link) == 0) {
      if (S_ISLNK(link.st_mode) || !S_ISDIR(link.st_mode))
        refuse(why_not_owned_directory(link),
               "contactsweep never follows or clears what it did not make; remove it if it is "
               "yours, else choose another path");
      if (link.st_uid != ::geteuid())  // unreadable to us: another user's
        refuse(why_not_owned_directory(link),
               "another user may have made it first; choose another path");
    }
    throw InputError(fmt::format("cannot open {} '{}': {}", purpose, path, errno_text(error)));
  }
  struct stat status {};
  if (::fstat(fd_, &status) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    throw InputError(fmt::format("cannot inspect {} '{}': {}", purpose, path, errno_text(error)));
  }
  if (const std::string why = why_not_owned_directory(status); !why.empty()) {
    ::close(fd_);
    fd_ = -1;
    refuse(why, status.st_uid == ::geteuid()
                    ? fmt::format("if only you can have put its content there, 'chmod go-w {}'", path)
                    : std::string("another user may have planted it; choose another path"));
  }
}

OwnedDirectory::~OwnedDirectory() {
  if (fd_ >= 0) ::close(fd_);
}

OwnedDirectory::OwnedDirectory(OwnedDirectory&& other) noexcept
    : path_(std::move(other.path_)), fd_(other.fd_), created_(other.created_) {
  other.fd_ = -1;
}

OwnedDirectory& OwnedDirectory::operator=(OwnedDirectory&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    created_ = other.created_;
    other.fd_ = -1;
  }
  return *this;
}

std::vector<std::string> OwnedDirectory::names() const {
  std::vector<std::string> out;
  const int copy = ::openat(fd_, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (copy < 0) return out;
  DIR* dir = ::fdopendir(copy);
  if (dir == nullptr) {
    ::close(copy);
    return out;
  }
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") out.push_back(name);
  }
  ::closedir(dir);
  return out;
}

bool OwnedDirectory::remove_file(const std::string& name) const {
  return ::unlinkat(fd_, name.c_str(), 0) == 0 || errno == ENOENT;
}

void OwnedDirectory::write_atomically(const std::string& name, const std::string& bytes,
                                      bool shared) const {
  // One writer per name: a temporary left by a killed writer is ours to replace (nobody else
  // can write here), and O_EXCL then proves the new one is the file we write.
  static std::atomic<unsigned> writes{0};
  const std::string tmp =
      shared ? fmt::format("{}.tmp.{}.{}", name, ::getpid(), writes++) : name + ".tmp";
  if (!shared) ::unlinkat(fd_, tmp.c_str(), 0);
  const int fd = ::openat(fd_, tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
                          0600);
  if (fd < 0) throw std::runtime_error("cannot create " + path_of(tmp) + ": " + errno_text(errno));
  auto give_up = [&](const std::string& what, int error) {
    ::close(fd);
    ::unlinkat(fd_, tmp.c_str(), 0);
    throw std::runtime_error("cannot " + what + " " + path_of(tmp) + ": " + errno_text(error));
  };
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) give_up("write", errno);
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) give_up("flush", errno);
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlinkat(fd_, tmp.c_str(), 0);
    throw std::runtime_error("cannot flush " + path_of(tmp) + ": " + errno_text(error));
  }
  if (::renameat(fd_, tmp.c_str(), fd_, name.c_str()) != 0) {
    const int error = errno;
    ::unlinkat(fd_, tmp.c_str(), 0);
    throw std::runtime_error("cannot rename " + path_of(tmp) + ": " + errno_text(error));
  }
}

void OwnedDirectory::sync_names() const {
  if (::fsync(fd_) != 0 && errno != EINVAL)
    throw std::runtime_error("cannot sync the directory " + path_ + ": " + errno_text(errno));
}

bool OwnedDirectory::read_file(const std::string& name, std::string& bytes, std::size_t most) const {
  // O_NONBLOCK: a FIFO under the name would block the open forever; S_ISREG then refuses it.
  const int fd = ::openat(fd_, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat status {};
  bool ok = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode) && status.st_uid == ::geteuid() &&
            static_cast<std::uint64_t>(status.st_size) <= most;
  if (ok) {
    try {  // a file far larger than memory (a sparse one, say) is unreadable, not fatal
      bytes.resize(static_cast<std::size_t>(status.st_size));
    } catch (const std::bad_alloc&) {
      ok = false;
      bytes.clear();
    }
  }
  if (ok) {
    std::size_t done = 0;
    while (ok && done < bytes.size()) {
      const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) ok = false;
      else done += static_cast<std::size_t>(n);
    }
  }
  ::close(fd);
  return ok;
}

}  // namespace cs
