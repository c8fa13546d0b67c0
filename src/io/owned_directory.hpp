// Directories this program writes into beside other people's files: the journal next to an
// output in a shared /scratch, the kernel cache. On a shared machine another user may have put
// anything under those names first: a link to the victim's data (which clearing the journal would
// then delete), a directory they can write to (where they plant a kernel that we would load).
//
// So such a directory is trusted only when it is a real directory (not a link), owned by this
// user and writable by nobody else; the check is made on the open descriptor, and every file
// inside is then reached relative to that descriptor (openat, unlinkat, renameat) without
// following links, never through the path again: a rename of the path after the check changes
// nothing. Directories we create are created 0700, whatever the umask.
#pragma once

#include <sys/stat.h>

#include <limits>
#include <string>
#include <vector>

namespace cs {

// Why the lstat of `path` is not a directory that only this user can change; "" when it is.
std::string why_not_owned_directory(const struct stat& status);

class OwnedDirectory {
 public:
  enum class Create { no, yes };

  // Opens `path`, creating it (mode 0700) when missing and `create` says so, its missing parents
  // too. Throws InputError naming `purpose`, the path, what is wrong and how to fix it. A
  // directory that does not exist and may not be created leaves `is_open()` false.
  OwnedDirectory(const std::string& path, const std::string& purpose, Create create);
  OwnedDirectory() = default;
  ~OwnedDirectory();
  OwnedDirectory(OwnedDirectory&& other) noexcept;
  OwnedDirectory& operator=(OwnedDirectory&& other) noexcept;
  OwnedDirectory(const OwnedDirectory&) = delete;
  OwnedDirectory& operator=(const OwnedDirectory&) = delete;

  bool is_open() const { return fd_ >= 0; }
  bool created() const { return created_; }  // by this object
  int fd() const { return fd_; }
  const std::string& path() const { return path_; }
  std::string path_of(const std::string& name) const { return path_ + "/" + name; }

  // The names of the entries (no "." or ".."), in no particular order.
  std::vector<std::string> names() const;

  // Removes the entry `name` if it is not a directory; never follows a link (a link is removed
  // itself). True when it is gone (or was never there).
  bool remove_file(const std::string& name) const;

  // Writes `bytes` to `name` so that `name` either keeps its old content or holds all of them:
  // a fresh temporary `name`.tmp (O_EXCL, no link followed), fsync, rename. One writer per
  // name at a time, unless `shared`: then each writer's temporary has a name of its own (and
  // one a killed writer left stays). Throws std::runtime_error.
  void write_atomically(const std::string& name, const std::string& bytes,
                        bool shared = false) const;

  // The whole content of the regular file `name`, opened without following a link (nor waiting
  // on a FIFO); false when it is missing, not a regular file, not this user's, larger than
  // `most` bytes or unreadable.
  bool read_file(const std::string& name, std::string& bytes,
                 std::size_t most = std::numeric_limits<std::size_t>::max()) const;

  // Makes the names written, renamed or removed in it so far survive a power cut (fsync of the
  // directory: a file's own fsync covers its data, not the entry that names it). Throws
  // std::runtime_error; a file system that cannot sync a directory (EINVAL) passes.
  void sync_names() const;

 private:
  std::string path_;
  int fd_ = -1;
  bool created_ = false;
};

}  // namespace cs
