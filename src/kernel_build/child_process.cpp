#include "kernel_build/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

extern char** environ;

namespace cs {
namespace {

// The variables GCC's driver, preprocessor and linker read to find files (GCC's manual,
// "Environment Variables Affecting GCC"), and their dependency outputs.
constexpr const char* kCompilerSearchVariables[] = {
    "CPATH",          "C_INCLUDE_PATH",      "CPLUS_INCLUDE_PATH", "OBJC_INCLUDE_PATH",
    "GCC_EXEC_PREFIX", "COMPILER_PATH",      "LIBRARY_PATH",       "DEPENDENCIES_OUTPUT",
    "SUNPRO_DEPENDENCIES", "GCC_COMPARE_DEBUG", "LD_RUN_PATH"};

std::string name_of(const std::string& entry) { return entry.substr(0, entry.find('=')); }

// PATH's absolute entries: an empty or relative one names the directory the compiler runs in.
std::string absolute_entries(const std::string& path) {
  std::string kept;
  std::size_t begin = 0;
  while (begin <= path.size()) {
    const std::size_t end = std::min(path.find(':', begin), path.size());
    const std::string dir = path.substr(begin, end - begin);
    if (!dir.empty() && dir[0] == '/') kept += (kept.empty() ? "" : ":") + dir;
    begin = end + 1;
  }
  return kept;
}

// Our environment without what would make the compiler read other files than ours: GCC's
// search paths, which a cluster's module system may point at shared directories and which the
// kernel's key does not cover, and PATH's relative and empty entries (the driver finds `as`
// and `ld` on PATH). One entry "NAME=value" per variable.
std::vector<std::string> compiler_environment() {
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry = *e;
    const std::string name = name_of(entry);
    if (std::any_of(std::begin(kCompilerSearchVariables), std::end(kCompilerSearchVariables),
                    [&](const char* v) { return name == v; }))
      continue;
    env.push_back(name == "PATH" ? "PATH=" + absolute_entries(entry.substr(5)) : entry);
  }
  return env;
}

// The file execvpe would start for `program`, found on PATH's absolute entries alone, or ""
// when none has it. execvpe searches the caller's PATH, relative entries included, and
// `compiler --version` runs in the user's directory (an output's shared one, say): "g++" with
// "." first on PATH would start a g++ planted there.
std::string program_file(const std::string& program) {
  if (program.find('/') != std::string::npos) return program;
  const char* path = std::getenv("PATH");
  const std::string dirs =
      absolute_entries(path != nullptr ? path : "/bin:/usr/bin");  // glibc's default
  for (std::size_t begin = 0; begin < dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', begin), dirs.size());
    const std::string file = dirs.substr(begin, end - begin) + "/" + program;
    struct stat status {};
    if (::stat(file.c_str(), &status) == 0 && S_ISREG(status.st_mode) &&
        ::access(file.c_str(), X_OK) == 0)
      return file;
    begin = end + 1;
  }
  return {};
}

}  // namespace

int run_program(const std::vector<std::string>& args, int output_fd,
                const std::vector<std::string>& extra_env, int directory_fd) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> env_text(extra_env);
  for (const std::string& entry : compiler_environment()) {
    const bool overridden = std::any_of(extra_env.begin(), extra_env.end(),
                                        [&](const auto& x) { return name_of(x) == name_of(entry); });
    if (!overridden) env_text.push_back(entry);
  }
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);

  const std::string file = program_file(args[0]);
  int exec_error[2];  // the child reports a failed exec here; closed on a successful one
  if (::pipe2(exec_error, O_CLOEXEC) != 0)
    throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(exec_error[0]);
    ::close(exec_error[1]);
    throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(error));
  }
  if (pid == 0) {  // only async-signal-safe calls from here on
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
    ::dup2(output_fd, 1);
    ::dup2(output_fd, 2);
    if (directory_fd >= 0 && ::fchdir(directory_fd) != 0) {
      const int error = errno;
      [[maybe_unused]] auto n = ::write(exec_error[1], &error, sizeof error);
      ::_exit(127);
    }
    if (!file.empty()) ::execvpe(file.c_str(), argv.data(), envp.data());  // a path: no search
    const int error = file.empty() ? ENOENT : errno;
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
        std::strerror(child_error),
        child_error == ENOENT
            ? ". contactsweep compiles each new K once (then caches it); install g++ or point "
              "CONTACTSWEEP_CXX at a C++20 compiler"
            : ""));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace cs
