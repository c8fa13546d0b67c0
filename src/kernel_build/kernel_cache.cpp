#include "kernel_build/kernel_cache.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/log.hpp"
#include "kernel_build/host_cpu.hpp"
#include "kernel_build/kernel_source.hpp"
#include "parallel/agreement.hpp"
#include "parallel/comm.hpp"
#include "parallel/run_identity.hpp"
#include "toolchain_config.hpp"
#include "version.hpp"

extern char** environ;

namespace cs {
namespace fs = std::filesystem;
namespace {

// How long a second builder waits for the first one before building its own copy.
constexpr double kLockWaitSeconds = 600.0;

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

// The headers a kernel includes: next to an installed program (PREFIX/bin/contactsweep →
// PREFIX/share/contactsweep/include), else in the source tree this program was built from.
std::string header_directory() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path installed = exe.parent_path() / toolchain_config::kInstalledIncludeDir;
    if (fs::exists(installed / "engine/block_runner.hpp", error))
      return fs::weakly_canonical(installed, error).string();
  }
  return toolchain_config::kSourceIncludeDir;
}

std::string hex64(std::uint64_t h) { return fmt::format("{:016x}", h); }

// Whether the flags build for the CPU they run on: then the kernel is fit for this kind of CPU
// only, and the key names it.
bool builds_for_this_cpu(const Toolchain& tc) {
  return std::any_of(tc.flags.begin(), tc.flags.end(), [](const std::string& flag) {
    return flag == "-march=native" || flag == "-mcpu=native";
  });
}

std::string cache_key(const std::string& source) {
  const Toolchain tc = toolchain();
  const std::string cpu = builds_for_this_cpu(tc) ? host_cpu_identity() : std::string();
  std::uint64_t h = fnv1a(source);
  for (const std::string& part : {tc.compiler, fmt::format("{}", fmt::join(tc.flags, " ")),
                                  std::string(kVersion), build_identity(), cpu})
    h = fnv1a(part, fnv1a(std::string_view("\0", 1), h));
  return hex64(h);
}

std::string read_tail(const std::string& path, std::size_t max_lines) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::string out;
  const std::size_t first = lines.size() > max_lines ? lines.size() - max_lines : 0;
  for (std::size_t i = first; i < lines.size(); ++i) out += "  " + lines[i] + "\n";
  return out;
}

// Runs the compiler with stdout and stderr into `log`; returns its exit status.
int run_compiler(const std::vector<std::string>& args, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw std::runtime_error(fmt::format(
        "cannot run the C++ compiler '{}' to build the kernel of scene.K: {}. contactsweep "
        "compiles each new K once (then caches it); install g++ or point CONTACTSWEEP_CXX at a "
        "C++20 compiler",
        args[0], std::strerror(spawned)));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Holds a write lock on `path` while alive, or nothing if none could be had in time.
class BuildLock {
 public:
  BuildLock(const std::string& path, const std::string& awaited) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) return;
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      struct flock request {};
      request.l_type = F_WRLCK;
      request.l_whence = SEEK_SET;
      if (::fcntl(fd_, F_OFD_SETLK, &request) == 0) return;
      if (errno != EAGAIN && errno != EACCES) break;  // ENOLCK etc.: build without it
      if (fs::exists(awaited)) break;  // the other builder finished
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

std::string private_suffix() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  return fmt::format("{}.{}", host, ::getpid());
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
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0')
    return std::string(xdg) + "/contactsweep";
  return env_or("HOME", "/tmp") + "/.cache/contactsweep";
}

std::string kernel_library_path(const std::string& source) {
  return kernel_cache_directory() + "/kernel-" + cache_key(source) + ".so";
}

BuiltKernel build_kernel(const std::string& source) {
  BuiltKernel built{kernel_library_path(source)};
  if (fs::exists(built.library)) return built;
  const std::string dir = kernel_cache_directory();
  std::error_code error;
  fs::create_directories(dir, error);
  if (error)
    throw std::runtime_error(fmt::format(
        "cannot create the kernel cache '{}': {} (set CONTACTSWEEP_CACHE to a writable directory)",
        dir, error.message()));
  const std::string stem = built.library.substr(0, built.library.size() - 3);
  BuildLock lock(stem + ".lock", built.library);
  if (fs::exists(built.library)) return built;  // built while we waited

  const std::string mine = stem + "." + private_suffix();
  const std::string source_file = mine + ".cpp", library = mine + ".so", log = stem + ".log";
  {
    std::ofstream out(source_file);
    out << source;
    if (!out.flush())
      throw std::runtime_error("cannot write the kernel source " + source_file);
  }
  const Toolchain tc = toolchain();
  if (builds_for_this_cpu(tc) && host_cpu_identity().empty())
    cs::log("contactsweep: warning: /proc/cpuinfo does not tell what CPU this is, so the kernel cache "
        "cannot keep kernels built with -march=native apart by CPU; machines of different kinds "
        "need CONTACTSWEEP_CACHE directories of their own");
  std::vector<std::string> args{tc.compiler};
  args.insert(args.end(), tc.flags.begin(), tc.flags.end());
  args.push_back("-I" + tc.include_dir);
  for (const auto& d : tc.system_include_dirs) args.push_back("-isystem" + d);
  args.insert(args.end(), {"-o", library, source_file});
  const auto start = std::chrono::steady_clock::now();
  const int status = run_compiler(args, log);
  built.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0 || !fs::exists(library)) {
    fs::remove(library, error);
    fs::rename(source_file, stem + ".cpp", error);
    throw std::runtime_error(fmt::format(
        "building the kernel of scene.K failed ({} exited with {}); its last messages:\n{}"
        "source: {}.cpp, full log: {}",
        tc.compiler, status, read_tail(log, 20), stem, log));
  }
  fs::rename(source_file, stem + ".cpp", error);  // kept beside the library, for the curious
  fs::remove(log, error);
  fs::rename(library, built.library, error);  // atomic: readers see all of it or nothing
  if (error)
    throw std::runtime_error(fmt::format("cannot move the kernel into the cache as '{}': {}",
                                         built.library, error.message()));
  built.compiled = true;
  return built;
}

KernelFn load_kernel(const std::string& library) {
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw std::runtime_error(fmt::format("cannot load the kernel '{}': {} (delete it to rebuild)",
                                         library, ::dlerror()));
  void* entry = ::dlsym(handle, kKernelEntry);
  if (entry == nullptr)
    throw std::runtime_error(
        fmt::format("the kernel '{}' has no entry point {} (delete it to rebuild)", library,
                    kKernelEntry));
  return reinterpret_cast<KernelFn>(entry);  // the handle stays open for the process's life
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
  return agreed(comm, [&] { return load_kernel(kernel_library_path(source)); });
}

}  // namespace cs
