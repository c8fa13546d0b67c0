#include "kernel_build/kernel_cache.hpp"

#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <pwd.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
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
#include "kernel_build/host_cpu.hpp"
#include "kernel_build/kernel_source.hpp"
#include "kernel_headers_hash.hpp"
#include "model/run_spec.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "parallel/run_identity.hpp"
#include "toolchain_config.hpp"
#include "version.hpp"

extern char** environ;

namespace cs {
namespace fs = std::filesystem;
namespace {

// How long a second builder waits for the first one before building its own copy.
constexpr double kLockWaitSeconds = 600.0;

constexpr const char* kCachePurpose = "the kernel cache";

// Appended to every library after linking (ELF ignores bytes past its sections): proves the file
// is whole and was made for this key before it is mapped, so neither a truncated file (SIGBUS
// inside dlopen) nor another K's kernel under this name is ever loaded.
constexpr char kTrailerMagic[8] = {'C', 'S', 'K', 'E', 'R', 'N', '0', '1'};
constexpr std::size_t kKeyChars = 16;
constexpr std::size_t kTrailerBytes = sizeof kTrailerMagic + kKeyChars + 2 * sizeof(std::uint64_t);

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

// The headers a kernel includes: the snapshot installed beside the program (PREFIX/bin/
// contactsweep -> PREFIX/share/contactsweep/include), else the build tree's.
std::string header_directory() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path installed = exe.parent_path() / toolchain_config::kInstalledIncludeDir;
    if (fs::exists(installed / "HEADERS_SHA256", error))
      return fs::weakly_canonical(installed, error).string();
  }
  return toolchain_config::kSnapshotIncludeDir;
}

// Whether the flags build for the CPU they run on: then the kernel is fit for this kind of CPU
// only, and the key names it.
bool builds_for_this_cpu(const Toolchain& tc) {
  return std::any_of(tc.flags.begin(), tc.flags.end(), [](const std::string& flag) {
    return flag == "-march=native" || flag == "-mcpu=native";
  });
}

// Runs `args` with stdout and stderr on `output_fd`; returns its exit status. The child dies
// with this process (a killed run leaves no compiler behind) and sees `extra_env` on top of
// ours. Throws when the program cannot be started, saying why (not found, not executable, ...).
int run_program(const std::vector<std::string>& args, int output_fd,
                const std::vector<std::string>& extra_env = {}) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> env_text(extra_env);
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry = *e;
    const bool overridden = std::any_of(extra_env.begin(), extra_env.end(), [&](const auto& x) {
      return entry.compare(0, x.find('=') + 1, x, 0, x.find('=') + 1) == 0;
    });
    if (!overridden) env_text.push_back(entry);
  }
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);

  int exec_error[2];  // the child reports a failed exec here; closed on a successful one
  if (::pipe2(exec_error, O_CLOEXEC) != 0)
    throw std::runtime_error("cannot start " + args[0] + ": " + errno_text(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(exec_error[0]);
    ::close(exec_error[1]);
    throw std::runtime_error("cannot start " + args[0] + ": " + errno_text(error));
  }
  if (pid == 0) {  // only async-signal-safe calls from here on
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
    ::dup2(output_fd, 1);
    ::dup2(output_fd, 2);
    ::execvpe(argv[0], argv.data(), envp.data());
    const int error = errno;
    [[maybe_unused]] auto n = ::write(exec_error[1], &error, sizeof error);
    ::_exit(127);
  }
  ::close(exec_error[1]);
  int child_error = 0;
  ssize_t got;
  while ((got = ::read(exec_error[0], &child_error, sizeof child_error)) < 0 && errno == EINTR) {
  }
  ::close(exec_error[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (got == static_cast<ssize_t>(sizeof child_error))
    throw std::runtime_error(fmt::format(
        "cannot run the C++ compiler '{}' to build the kernel of scene.K: {}{}", args[0],
        errno_text(child_error),
        child_error == ENOENT
            ? ". contactsweep compiles each new K once (then caches it); install g++ or point "
              "CONTACTSWEEP_CXX at a C++20 compiler"
            : ""));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The compiler's file as found on PATH: its path and what the file system says of it (device,
// inode, size, modification and change times), or "" when it is not found. An upgrade or a
// switch of the symlink g++ -> g++-N changes it; the change time cannot be set back by anyone.
std::string compiler_file_signature(const std::string& compiler) {
  std::vector<std::string> candidates;
  if (compiler.find('/') != std::string::npos) {
    candidates.push_back(compiler);
  } else {
    for (const std::string& dir : split(env_or("PATH", "/usr/bin:/bin"), ':'))
      candidates.push_back(dir + "/" + compiler);
  }
  for (const std::string& path : candidates) {
    struct stat status {};
    if (::stat(path.c_str(), &status) == 0 && S_ISREG(status.st_mode) &&
        ::access(path.c_str(), X_OK) == 0)
      return fmt::format("{} {} {} {} {}.{} {}.{}", path, status.st_dev, status.st_ino,
                         status.st_size, status.st_mtim.tv_sec, status.st_mtim.tv_nsec,
                         status.st_ctim.tv_sec, status.st_ctim.tv_nsec);
  }
  return {};
}

// Runs `compiler --version` and returns what it prints.
std::string ask_version(const std::string& compiler) {
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0)
    throw std::runtime_error("cannot ask the compiler its version: " + errno_text(errno));
  std::string text;
  int status = 0;
  std::thread reader([&] {  // drains the pipe while the child writes (no deadlock on long text)
    char buffer[4096];
    for (ssize_t n; (n = ::read(out[0], buffer, sizeof buffer)) != 0;) {
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) break;
      text.append(buffer, static_cast<std::size_t>(n));
    }
  });
  try {
    status = run_program({compiler, "--version"}, out[1]);
  } catch (...) {
    ::close(out[1]);
    reader.join();
    ::close(out[0]);
    throw;
  }
  ::close(out[1]);
  reader.join();
  ::close(out[0]);
  if (status != 0)
    throw std::runtime_error(fmt::format("the C++ compiler '{}' failed to tell its version "
                                         "(exit status {}): {}", compiler, status, text));
  return text;
}

// The compiler's identity as it reports it (`--version`): an upgraded compiler under the same
// path builds another key. Starting a compiler costs milliseconds, so the answer is kept in the
// cache under the signature of the compiler's file and asked again only when that changes.
std::string compiler_identity(const std::string& compiler) {
  static std::mutex mutex;
  static std::map<std::string, std::string> known;
  const std::lock_guard<std::mutex> lock(mutex);
  const std::string signature = compiler_file_signature(compiler);
  const std::string memo_key = compiler + '\0' + signature;
  if (auto it = known.find(memo_key); it != known.end()) return it->second;
  const std::string memo = fmt::format("compiler-{:016x}.id", fnv1a(memo_key));
  OwnedDirectory cache;
  try {
    if (!signature.empty())
      cache = OwnedDirectory(kernel_cache_directory(), kCachePurpose, OwnedDirectory::Create::no);
  } catch (const InputError&) {  // an untrusted cache: refused where it is used, not here
  }
  std::string text;
  if (cache.is_open() && cache.read_file(memo, text)) return known[memo_key] = text;
  text = ask_version(compiler);
  if (cache.is_open()) {
    try {
      cache.write_atomically(memo, text, /*shared=*/true);
    } catch (const std::exception&) {  // only a memo: asked again next time
    }
  }
  return known[memo_key] = text;
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

void check_library(const OwnedDirectory& dir, const std::string& name, const std::string& key,
                   CheckedLibrary& out) {
  out.fd = ::openat(dir.fd(), name.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (out.fd < 0) {
    out.missing = errno == ENOENT;
    out.problem = errno == ELOOP ? "it is a symbolic link" : errno_text(errno);
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

// The headers in `dir` are the snapshot this program was built with, or the build is refused:
// a kernel compiled from other headers would be called with other layouts.
void check_headers(const std::string& dir) {
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
                                    errno_text(error));
}

OwnedDirectory open_cache(OwnedDirectory::Create create) {
  return OwnedDirectory(kernel_cache_directory(), kCachePurpose, create);
}

}  // namespace

Toolchain toolchain() {
  Toolchain tc;
  tc.compiler = env_or("CONTACTSWEEP_CXX", toolchain_config::kCompiler);
  tc.flags = split(toolchain_config::kFlags, ' ');
  tc.flags.push_back("-fPIC");
  tc.flags.push_back("-shared");
  tc.include_dir = header_directory();
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
  std::uint64_t h = fnv1a(source);
  for (const std::string& part :
       {tc.compiler, compiler_identity(tc.compiler), fmt::format("{}", fmt::join(tc.flags, " ")),
        std::string(kVersion), build_identity(), cpu, std::string(kKernelHeadersHash)})
    h = fnv1a(part, fnv1a(std::string_view("\0", 1), h));
  return fmt::format("{:016x}", h);
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
  const OwnedDirectory work(dir.path_of(build_name), kCachePurpose, OwnedDirectory::Create::no);
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
  args.insert(args.end(), {"-o", work.path_of("kernel.so"), work.path_of("kernel.cpp")});
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  try {
    status = run_program(args, log_fd, {"TMPDIR=" + work.path()});  // its temporaries too
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

KernelFn load_kernel(const std::string& source) {
  const std::string key = kernel_key(source), name = library_name(key);
  const OwnedDirectory dir = open_cache(OwnedDirectory::Create::no);
  const std::string path = dir.is_open() ? dir.path_of(name) : kernel_cache_directory() + "/" + name;
  CheckedLibrary library;
  if (dir.is_open()) check_library(dir, name, key, library);
  if (!dir.is_open() || !library.problem.empty())
    throw std::runtime_error(fmt::format("cannot load the kernel '{}': {}", path,
                                         dir.is_open() ? library.problem : "the cache is missing"));
  // Loaded through the descriptor that was checked: what is mapped is what was read.
  const std::string by_descriptor = fmt::format("/proc/self/fd/{}", library.fd);
  const bool proc = ::access(by_descriptor.c_str(), R_OK) == 0;
  void* handle = ::dlopen(proc ? by_descriptor.c_str() : path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw std::runtime_error(fmt::format("cannot load the kernel '{}': {}", path, ::dlerror()));
  const auto* stamped = static_cast<const char*>(::dlsym(handle, kKernelKeySymbol));
  if (stamped == nullptr || key != stamped)
    throw std::runtime_error(fmt::format("the kernel '{}' was not built for this K (its key: {}; "
                                         "expected {})", path, stamped ? stamped : "none", key));
  void* entry = ::dlsym(handle, kKernelEntry);
  if (entry == nullptr)
    throw std::runtime_error(
        fmt::format("the kernel '{}' has no entry point {}", path, kKernelEntry));
  // The handle stays open for the process's life, and so does the descriptor: the loader knows
  // the library by its name /proc/self/fd/N, and would hand it out again for a later kernel
  // loaded through a reused N.
  library.fd = -1;
  return reinterpret_cast<KernelFn>(entry);
}

KernelFn prepare_kernel(const std::string& source, MPI_Comm comm, BuiltKernel* built) {
  int node_rank = 0;
  MPI_Comm node = MPI_COMM_NULL;
  if (!serial(comm)) {
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank_of(comm), MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &node_rank);
  }
  BuiltKernel mine;
  std::exception_ptr failure;
  try {
    if (node_rank == 0) mine = build_kernel(source);
  } catch (...) {
    failure = std::current_exception();
  }
  if (node != MPI_COMM_NULL) MPI_Comm_free(&node);
  throw_if_any_failed(comm, failure);
  if (built != nullptr) *built = mine;
  return agreed(comm, [&] { return load_kernel(source); });
}

}  // namespace cs
