#include "kernel_build/kernel_cache.hpp"

#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <grp.h>
#include <pwd.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/log.hpp"
#include "io/owned_directory.hpp"
#include "kernel_build/child_process.hpp"
#include "kernel_build/compiler_identity.hpp"
#include "kernel_build/host_cpu.hpp"
#include "kernel_build/kernel_source.hpp"
#include "kernel_build/sealed_library.hpp"
#include "kernel_build/sha256.hpp"
#include "kernel_headers_hash.hpp"
#include "model/run_spec.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "parallel/run_identity.hpp"
#include "toolchain_config.hpp"
#include "version.hpp"

namespace cs {
namespace fs = std::filesystem;
namespace {

// How long a second builder waits for the first one before building its own copy.
constexpr double kLockWaitSeconds = 600.0;


std::string errno_text(int error) { return std::strerror(error); }

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, separator);)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

std::string env_or(const char* name, const std::string& fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? std::string(value) : fallback;
}

std::string host_name() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  return host;
}

// The file holding this code: the program (PREFIX/bin/contactsweep), or the Python module
// (PREFIX/lib/python3.X/dist-packages/contactsweep/_core*.so) inside the interpreter, whose
// /proc/self/exe is python3. dladdr names a shared object by its absolute path; the program
// it may name as started (relative), hence /proc/self/exe for it.
fs::path code_file() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&code_file), &info) != 0 && info.dli_fname != nullptr &&
      info.dli_fname[0] == '/')
    return info.dli_fname;
  std::error_code error;
  return fs::read_symlink("/proc/self/exe", error);
}

// A kernel calls the engine's code that does not depend on the scene in the file holding this
// code (engine/engine_export.hpp). The program's exports are in the global scope of every library
// it loads. The Python module, which python3 loads with RTLD_LOCAL, is instead named as the
// kernel's own dependency by its absolute path: the loader finds that file already loaded (by
// device and inode) and puts it in the kernel's scope alone, so nothing of the module or its
// libraries (HDF5, MPI) becomes global for the libraries Python loads later, and a kernel binds
// to the module that built it even beside another build of contactsweep.
std::vector<std::string> host_library() {
  const fs::path code = code_file();
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  if (code.empty() || fs::equivalent(code, program, error) || error) return {};
  return {code.string()};
}

// Whether files of `owner` may be compiled into a kernel: root's, ours, and those of the owner
// of the code file running (whose code we run anyway: a software tree an admin account installed).
bool trusted_owner(uid_t owner) {
  static const uid_t code_owner = [] {
    struct stat status {};
    const fs::path code = code_file();
    return !code.empty() && ::stat(code.c_str(), &status) == 0 ? status.st_uid : 0;
  }();
  return owner == 0 || owner == ::geteuid() || owner == code_owner;
}

// Whether the only users in group `gid` are ones trusted_owner trusts: a user private group (the
// one whose name is its user's and who has it as primary group, no other member listed) of
// root, ours or the code's owner. Group-writable files in such a group are what a build under a
// umask of 002 leaves (Debian's and Ubuntu's default for users with a group of their own).
bool private_group_of_trusted(gid_t gid) {
  static std::mutex mutex;
  static std::map<gid_t, bool> known;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto it = known.find(gid); it != known.end()) return it->second;
  bool trusted = false;
  struct group group_entry {}, *group = nullptr;
  std::vector<char> group_buffer(65536);
  if (::getgrgid_r(gid, &group_entry, group_buffer.data(), group_buffer.size(), &group) == 0 &&
      group != nullptr && group->gr_name != nullptr) {
    struct passwd user_entry {}, *user = nullptr;
    std::vector<char> user_buffer(16384);
    trusted = ::getpwnam_r(group->gr_name, &user_entry, user_buffer.data(), user_buffer.size(),
                           &user) == 0 &&
              user != nullptr && user->pw_gid == gid && trusted_owner(user->pw_uid);
    for (char** member = group->gr_mem; trusted && member != nullptr && *member != nullptr; ++member)
      trusted = std::strcmp(*member, group->gr_name) == 0;
  }
  return known[gid] = trusted;
}

// Why the headers in `dir` may be another user's, or "" when only root, we and the owner of
// the code file running (whose code we run anyway: a software tree an admin account installed)
// can have put them there: `dir`, everything in it and every directory above it that is not
// also above the code file (where the code file is just as exposed) is theirs, and nobody else
// can write to it (but for sticky directories above: others may add names there, not replace
// ours; and a group that is a private group of one of those users). The installed candidates below are found by
// climbing from the code file's directory, up to 4 levels: for a program or module that is not
// installed (a build tree 4 levels below /tmp, a checkout in a shared /scratch) they are
// directories anyone may create; the build tree's snapshot is named by its absolute path, which
// anyone may create once a build tree in /tmp is gone and its program lives on elsewhere.
std::string untrusted_headers(const std::string& dir) {
  std::error_code error;
  const fs::path code = code_file();
  const fs::path code_dir =
      code.empty() ? fs::path() : fs::weakly_canonical(code.parent_path(), error);
  const auto problem = [&](const fs::path& path, bool above) -> std::string {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0)
      return fmt::format("'{}' cannot be examined ({})", path.string(), errno_text(errno));
    if (!trusted_owner(status.st_uid))
      return fmt::format("'{}' belongs to user id {}", path.string(), status.st_uid);
    const bool others_write =
        (status.st_mode & S_IWOTH) != 0 ||
        ((status.st_mode & S_IWGRP) != 0 && !private_group_of_trusted(status.st_gid));
    if (others_write && !(above && S_ISDIR(status.st_mode) && (status.st_mode & S_ISVTX) != 0))
      return fmt::format("others can write to '{}'", path.string());
    return {};
  };
  const auto above_code = [&](const fs::path& path) {
    return !code_dir.empty() &&
           std::mismatch(path.begin(), path.end(), code_dir.begin(), code_dir.end()).first ==
               path.end();
  };
  const fs::path canonical = fs::weakly_canonical(dir, error);
  for (fs::path up = canonical.parent_path(); !up.empty() && !above_code(up);
       up = up.parent_path()) {
    if (std::string why = problem(up, true); !why.empty()) return why;
    if (up == up.root_path()) break;
  }
  if (std::string why = problem(canonical, false); !why.empty()) return why;
  for (fs::recursive_directory_iterator
           it(canonical, fs::directory_options::follow_directory_symlink, error),
       end;
       !error && it != end; it.increment(error))
    if (std::string why = problem(it->path(), false); !why.empty()) return why;
  if (error) return fmt::format("'{}' cannot be listed ({})", canonical.string(), error.message());
  return {};
}

// The headers a kernel includes: the snapshot installed beside the program (PREFIX/bin/
// contactsweep -> PREFIX/share/contactsweep/include) or the module (4 levels below PREFIX),
// else the build tree's. An installed-looking directory that another user may have made is
// passed over, with a warning: its headers would be compiled into a kernel this process loads.
std::string find_header_directory() {
  std::error_code error;
  const fs::path code = code_file();
  if (code.empty()) return toolchain_config::kSnapshotIncludeDir;
  for (const fs::path& relative :
       {fs::path(toolchain_config::kInstalledIncludeDir),
        fs::path("../../..") / toolchain_config::kInstalledIncludeDir}) {
    const fs::path installed = code.parent_path() / relative;
    if (!fs::exists(installed / "HEADERS_SHA256", error)) continue;
    const fs::path canonical = fs::weakly_canonical(installed, error);
    // The checks below see the canonical path alone, where a link on the way down from the
    // code file's directory is already followed: one another user made (/scratch/share ->
    // another installation's headers) would choose the headers, and fail every kernel's build.
    std::string why;
    fs::path way = code.parent_path();
    for (const fs::path& part : relative) {
      way /= part;
      struct stat status {};
      if (why.empty() && part != ".." && ::lstat(way.c_str(), &status) == 0 &&
          S_ISLNK(status.st_mode) && !trusted_owner(status.st_uid))
        why = fmt::format("'{}' is a link that user id {} made", way.lexically_normal().string(),
                          status.st_uid);
    }
    if (why.empty()) why = untrusted_headers(canonical);
    if (!why.empty()) {
      log("contactsweep: warning: not compiling kernels against the headers in '{}': {}, so "
          "another user may have put them there",
          canonical.string(), why);
      continue;
    }
    return canonical.string();
  }
  // Canonical, as the one checked: a link on the way is not followed again by the compiler.
  const fs::path snapshot = fs::weakly_canonical(toolchain_config::kSnapshotIncludeDir, error);
  return error || snapshot.empty() ? std::string(toolchain_config::kSnapshotIncludeDir)
                                   : snapshot.string();
}

// Looked for once a process: the program's place does not change while it runs.
std::string header_directory() {
  static const std::string dir = find_header_directory();
  return dir;
}

// Whether the flags build for the CPU they run on: then the kernel is fit for this kind of CPU
// only, and the key names it.
bool builds_for_this_cpu(const Toolchain& tc) {
  return std::any_of(tc.flags.begin(), tc.flags.end(), [](const std::string& flag) {
    return flag == "-march=native" || flag == "-mcpu=native";
  });
}

// Where the user's home is: HOME, else the passwd entry's (batch jobs may have no HOME).
std::string home_directory() {
  if (const char* home = std::getenv("HOME"); home != nullptr && *home == '/') return home;
  struct passwd entry {}, *found = nullptr;
  std::vector<char> buffer(16384);
  if (::getpwuid_r(::geteuid(), &entry, buffer.data(), buffer.size(), &found) == 0 &&
      found != nullptr && found->pw_dir != nullptr && found->pw_dir[0] == '/' &&
      std::string_view(found->pw_dir) != "/")
    return found->pw_dir;
  return {};
}

// Holds a write lock on `name` in `dir` while alive, or nothing if none could be had in time.
class BuildLock {
 public:
  BuildLock(const OwnedDirectory& dir, const std::string& name, const std::string& awaited) {
    fd_ = ::openat(dir.fd(), name.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd_ < 0) return;
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      struct flock request {};
      request.l_type = F_WRLCK;
      request.l_whence = SEEK_SET;
      if (::fcntl(fd_, F_OFD_SETLK, &request) == 0) return;
      if (errno != EAGAIN && errno != EACCES) break;  // ENOLCK etc.: build without it
      struct stat status {};
      if (::fstatat(dir.fd(), awaited.c_str(), &status, AT_SYMLINK_NOFOLLOW) == 0)
        break;  // the other builder finished
      const double waited =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (waited > kLockWaitSeconds) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ::close(fd_);
    fd_ = -1;
  }
  ~BuildLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  BuildLock(const BuildLock&) = delete;
  BuildLock& operator=(const BuildLock&) = delete;

 private:
  int fd_ = -1;
};

// Private build directories are named build.<pid>.<n>.<host>: one left by a process of this
// host that no longer lives (killed mid-compile) is removed with what its compiler left in it.
// Nobody else can have written there: the cache is ours alone.
bool is_stale_build(const std::string& name) {
  if (name.rfind("build.", 0) != 0) return false;
  const auto pid_end = name.find('.', 6), n_end = name.find('.', pid_end + 1);
  if (pid_end == std::string::npos || n_end == std::string::npos) return false;
  if (name.substr(n_end + 1) != host_name()) return false;
  const pid_t pid = static_cast<pid_t>(std::strtol(name.c_str() + 6, nullptr, 10));
  return pid > 0 && pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

void remove_build_directory(const OwnedDirectory& cache, const std::string& name) {
  const int fd = ::openat(cache.fd(), name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd >= 0) {
    if (DIR* dir = ::fdopendir(fd)) {
      std::vector<std::string> names;
      while (const dirent* entry = ::readdir(dir))
        if (std::strcmp(entry->d_name, ".") != 0 && std::strcmp(entry->d_name, "..") != 0)
          names.emplace_back(entry->d_name);
      for (const auto& n : names) ::unlinkat(::dirfd(dir), n.c_str(), 0);  // files only
      ::closedir(dir);
    } else {
      ::close(fd);
    }
  }
  ::unlinkat(cache.fd(), name.c_str(), AT_REMOVEDIR);
}

void remove_stale_builds(const OwnedDirectory& cache) {
  for (const std::string& name : cache.names())
    if (is_stale_build(name)) remove_build_directory(cache, name);
}

// The headers in `dir` are the snapshot this program was built with, and none another user may
// have put there or changed, or the build is refused: a kernel compiled from other headers
// would be called with other layouts, or run their code. Writable by others, the build tree's
// snapshot is as exposed as an installed copy: a program copied out of a group's build tree
// (~/bin) compiled what any member of the group wrote into it (its precompiled header too).
void check_headers(const std::string& dir) {
  if (const std::string why = untrusted_headers(dir); !why.empty())
    throw std::runtime_error(fmt::format(
        "not compiling kernels against the headers in '{}': {}, so another user may have put "
        "them there; {}",
        dir, why,
        why.rfind("others can write", 0) == 0
            ? "if only you can have changed them, make them writable by their owner alone "
              "(chmod -R go-w), else rebuild contactsweep or install it again"
            : "rebuild contactsweep (cmake --build) or install it again (cmake --install)"));
  std::string text;
  const int fd = ::open((dir + "/HEADERS_SHA256").c_str(), O_RDONLY | O_CLOEXEC);
  if (fd >= 0) {
    char buffer[128];
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    ::close(fd);
    if (n > 0) text.assign(buffer, static_cast<std::size_t>(n));
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (text != kKernelHeadersHash)
    throw std::runtime_error(fmt::format(
        "the kernel headers in '{}' are not the ones this contactsweep was built with (their "
        "hash is '{}', this program's is {}): rebuild it (cmake --build) or install it again",
        dir, text, kKernelHeadersHash));
}

std::string read_tail(const OwnedDirectory& dir, const std::string& name, std::size_t max_lines) {
  std::string bytes;
  dir.read_file(name, bytes);
  std::vector<std::string> lines = split(bytes, '\n');
  std::string out;
  const std::size_t first = lines.size() > max_lines ? lines.size() - max_lines : 0;
  for (std::size_t i = first; i < lines.size(); ++i) out += "  " + lines[i] + "\n";
  return out;
}

OwnedDirectory open_cache(OwnedDirectory::Create create) {
  return OwnedDirectory(kernel_cache_directory(), kKernelCachePurpose, create);
}

}  // namespace

Toolchain toolchain() {
  Toolchain tc;
  tc.compiler = env_or("CONTACTSWEEP_CXX", toolchain_config::kCompiler);
  tc.flags = split(toolchain_config::kFlags, ' ');
  tc.flags.push_back("-fPIC");
  tc.flags.push_back("-shared");
  tc.include_dir = header_directory();
  tc.link_inputs = host_library();
  tc.system_include_dirs = split(toolchain_config::kMpiIncludeDirs, ';');
  return tc;
}

std::string kernel_cache_directory() {
  if (const char* dir = std::getenv("CONTACTSWEEP_CACHE"); dir != nullptr && *dir != '\0')
    return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/')
    return std::string(xdg) + "/contactsweep";
  const std::string home = home_directory();
  if (home.empty())
    throw InputError(
        "there is no home directory to keep the kernel of scene.K in (HOME is unset and the "
        "user has no home in the passwd database); set CONTACTSWEEP_CACHE to a directory of "
        "your own");
  return home + "/.cache/contactsweep";
}

std::string kernel_key(const std::string& source) {
  const Toolchain tc = toolchain();
  const std::string cpu = builds_for_this_cpu(tc) ? host_cpu_identity() : std::string();
  // SHA-256, not FNV-1a: the source holds K's text, so a spec could be padded until its key
  // met another K's, whose later runs would then load its kernel (kernel_build/sha256.hpp).
  Sha256 h;
  h.add(source);
  for (const std::string& part :
       {tc.compiler, compiler_identity(tc.compiler), fmt::format("{}", fmt::join(tc.flags, " ")),
        fmt::format("{}", fmt::join(tc.link_inputs, " ")), std::string(kVersion), build_identity(), cpu, std::string(kKernelHeadersHash)})
    h.add(std::string_view("\0", 1)).add(part);
  return hex_of(h.digest(), kKernelKeyDigits);
}

BuiltKernel build_kernel(const std::string& source) {
  const std::string key = kernel_key(source), name = library_name(key);
  const OwnedDirectory dir = open_cache(OwnedDirectory::Create::yes);
  BuiltKernel built{dir.path_of(name)};
  auto cached = [&] {
    CheckedLibrary library;
    check_library(dir, name, key, library);
    if (library.problem.empty()) return true;
    if (!library.missing) {  // ours to replace: the directory is ours alone
      log("contactsweep: the cached kernel '{}' is not fit to load ({}); building it again",
          built.library, library.problem);
      dir.remove_file(name);
    }
    return false;
  };
  if (cached()) return built;
  const BuildLock lock(dir, "kernel-" + key + ".lock", name);
  if (cached()) return built;  // built while we waited
  remove_stale_builds(dir);

  const Toolchain tc = toolchain();
  check_headers(tc.include_dir);
  if (builds_for_this_cpu(tc) && host_cpu_identity().empty())
    log("contactsweep: warning: /proc/cpuinfo does not tell what CPU this is, so the kernel cache "
        "cannot keep kernels built with -march=native apart by CPU; machines of different kinds "
        "need CONTACTSWEEP_CACHE directories of their own");

  // A private directory for this build: the source's own directory is searched first for its
  // quoted #includes, so nothing but the source may be there.
  static std::atomic<int> builds{0};
  const std::string build_name = fmt::format("build.{}.{}.{}", ::getpid(), builds++, host_name());
  if (::mkdirat(dir.fd(), build_name.c_str(), 0700) != 0)
    throw std::runtime_error("cannot create a build directory in the kernel cache '" +
                             dir.path() + "': " + errno_text(errno));
  struct RemoveBuild {
    const OwnedDirectory& cache;
    const std::string& name;
    ~RemoveBuild() { remove_build_directory(cache, name); }
  } remove_build{dir, build_name};
  const OwnedDirectory work(dir.path_of(build_name), kKernelCachePurpose, OwnedDirectory::Create::no);
  if (!work.is_open())
    throw std::runtime_error("the build directory " + dir.path_of(build_name) + " vanished");
  work.write_atomically("kernel.cpp", with_kernel_key(source, key));
  const int log_fd = ::openat(work.fd(), "compile.log",
                              O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (log_fd < 0)
    throw std::runtime_error("cannot create " + work.path_of("compile.log") + ": " +
                             errno_text(errno));

  std::vector<std::string> args{tc.compiler};
  args.insert(args.end(), tc.flags.begin(), tc.flags.end());
  args.push_back("-I" + tc.include_dir);
  for (const auto& d : tc.system_include_dirs) args.push_back("-isystem" + d);
  // Run in the build directory, entered by its descriptor, with names relative to it: a path
  // through the cache's parents would let anyone who can rename one of them hand the compiler
  // their source, or the assembler their code, between our checks and its reads.
  args.insert(args.end(), {"-o", "kernel.so", "kernel.cpp"});
  args.insert(args.end(), tc.link_inputs.begin(), tc.link_inputs.end());
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  try {
    status = run_program(args, log_fd, {"TMPDIR=."}, work.fd());  // its temporaries there too
  } catch (...) {
    ::close(log_fd);
    throw;
  }
  ::close(log_fd);
  built.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string stem = "kernel-" + key;
  struct stat linked {};
  if (status != 0 || ::fstatat(work.fd(), "kernel.so", &linked, AT_SYMLINK_NOFOLLOW) != 0) {
    const std::string tail = read_tail(work, "compile.log", 20);
    // Kept for the user: renameat replaces a name, never writes through a link.
    ::renameat(work.fd(), "kernel.cpp", dir.fd(), (stem + ".cpp").c_str());
    ::renameat(work.fd(), "compile.log", dir.fd(), (stem + ".log").c_str());
    throw std::runtime_error(fmt::format(
        "building the kernel of scene.K failed ({} exited with {}); its last messages:\n{}"
        "source: {}, full log: {}",
        tc.compiler, status, tail, dir.path_of(stem + ".cpp"), dir.path_of(stem + ".log")));
  }
  seal_library(work, "kernel.so", key);
  ::renameat(work.fd(), "kernel.cpp", dir.fd(), (stem + ".cpp").c_str());  // for the curious
  if (::renameat(work.fd(), "kernel.so", dir.fd(), name.c_str()) != 0)  // atomic
    throw std::runtime_error(fmt::format("cannot move the kernel into the cache as '{}': {}",
                                         built.library, errno_text(errno)));
  built.compiled = true;
  return built;
}

void* load_kernel(const std::string& source, const char* entry_name) {
  const std::string key = kernel_key(source), name = library_name(key);
  const OwnedDirectory dir = open_cache(OwnedDirectory::Create::no);
  const std::string path = dir.is_open() ? dir.path_of(name) : kernel_cache_directory() + "/" + name;
  CheckedLibrary library;
  if (dir.is_open()) check_library(dir, name, key, library);
  if (!dir.is_open() || !library.problem.empty())
    throw std::runtime_error(fmt::format("cannot load the kernel '{}': {}", path,
                                         dir.is_open() ? library.problem : "the cache is missing"));
  // Loaded through the descriptor that was checked: what is mapped is what was read. Without
  // /proc that descriptor has no name, and the library's path is not loaded instead: someone
  // who can rename a parent of the cache could swap it between the check and the load.
  const std::string by_descriptor = fmt::format("/proc/self/fd/{}", library.fd);
  if (::access(by_descriptor.c_str(), R_OK) != 0)
    throw std::runtime_error(fmt::format(
        "cannot load the kernel '{}' through the descriptor it was checked on ({}: {}); "
        "contactsweep loads kernels only that way, so /proc must be mounted",
        path, by_descriptor, errno_text(errno)));
  void* handle = ::dlopen(by_descriptor.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw std::runtime_error(fmt::format("cannot load the kernel '{}': {}", path, ::dlerror()));
  // A library refused after loading is closed again: the loader would otherwise keep it under
  // the name /proc/self/fd/N and hand it out for a later kernel loaded through a reused N.
  const auto refuse = [&](const std::string& why) {
    ::dlclose(handle);
    throw std::runtime_error(why);
  };
  const auto* stamped = static_cast<const char*>(::dlsym(handle, kKernelKeySymbol));
  if (stamped == nullptr || key != stamped)
    refuse(fmt::format("the kernel '{}' was not built for this K (its key: {}; expected {})", path,
                       stamped ? std::string(stamped) : "none", key));
  void* entry = ::dlsym(handle, entry_name);
  if (entry == nullptr) refuse(fmt::format("the kernel '{}' has no entry point {}", path, entry_name));
  // The handle stays open for the process's life, and so does the descriptor: the loader knows
  // the library by its name /proc/self/fd/N, and would hand it out again for a later kernel
  // loaded through a reused N.
  library.fd = -1;
  return entry;
}

void* prepare_kernel(const std::string& source, const char* entry, MPI_Comm comm,
                     BuiltKernel* built, const std::string* beside, BuiltKernel* built_beside) {
  int node_rank = 0;
  MPI_Comm node = MPI_COMM_NULL;
  if (!serial(comm)) {
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank_of(comm), MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &node_rank);
  }
  BuiltKernel mine, other;
  std::exception_ptr failure;
  {
    // The second build's thread: joined before this scope ends, whatever happens.
    std::jthread second;
    if (node_rank == 0 && beside != nullptr)
      second = std::jthread([&] {
        try {
          other = build_kernel(*beside);
        } catch (...) {  // its own build, when the run needs it, says what went wrong
        }
      });
    try {
      if (node_rank == 0) mine = build_kernel(source);
    } catch (...) {
      failure = std::current_exception();
    }
  }
  if (built_beside != nullptr) *built_beside = other;
  if (node != MPI_COMM_NULL) MPI_Comm_free(&node);
  throw_if_any_failed(comm, failure);
  if (built != nullptr) *built = mine;
  return agreed(comm, [&] { return load_kernel(source, entry); });
}

}  // namespace cs
