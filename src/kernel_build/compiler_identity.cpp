#include "kernel_build/compiler_identity.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "io/owned_directory.hpp"
#include "kernel_build/child_process.hpp"
#include "kernel_build/kernel_cache.hpp"
#include "model/run_spec.hpp"
#include "parallel/run_identity.hpp"

namespace cs {
namespace {

// The compiler's file as found on PATH: its path and what the file system says of it (device,
// inode, size, modification and change times), or "" when it is not found. An upgrade or a
// switch of the symlink g++ -> g++-N changes it; the change time cannot be set back by anyone.
std::string compiler_file_signature(const std::string& compiler) {
  std::vector<std::string> candidates;
  if (compiler.find('/') != std::string::npos) {
    candidates.push_back(compiler);
  } else {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path != nullptr && *path != '\0' ? path : "/usr/bin:/bin");
    for (std::string dir; std::getline(dirs, dir, ':');)
      if (!dir.empty() && dir[0] == '/')
        candidates.push_back(dir + "/" + compiler);  // as run_program
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
    throw std::runtime_error(std::string("cannot ask the compiler its version: ") + std::strerror(errno));
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

}  // namespace

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
      cache = OwnedDirectory(kernel_cache_directory(), kKernelCachePurpose, OwnedDirectory::Create::no);
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

}  // namespace cs
