// Kernels of custom scenes, compiled once and kept: the generated source is compiled by the
// compiler and with the flags this program was built with, against the snapshot of the headers
// it was built from (snapshot_headers.cmake), into a shared object cached under a key in
// $CONTACTSWEEP_CACHE, else $XDG_CACHE_HOME/contactsweep, else ~/.cache/contactsweep (HOME, else
// the passwd entry's home; never a shared fallback such as /tmp). The key hashes the source, the
// compiler's path and `--version` output, the flags, the program's version and build-id, the
// headers' hash and, when the flags say -march=native, the CPU (host_cpu.hpp).
//
// The cache is a trust boundary: a library in it is loaded into this process, so anyone who can
// write there can run code as this user. The directory must be this user's and writable by
// nobody else (io/owned_directory.hpp; created 0700), and every library is checked before it is
// loaded: a regular file of ours, whole (a trailer with its size and checksum, appended after
// linking) and made for this very key (the trailer, and an exported constant checked after
// loading). A library that fails the check is rebuilt. Sources are compiled in a private
// directory of their own, so nothing planted beside them is included, and every file is made
// there with O_EXCL and renamed into place.
//
// Concurrent builders of the same kernel (ranks of a node, jobs sharing a home directory) build
// it once: the builder holds a lock on KEY.lock, compiles in its private directory and renames
// the result into place atomically; the others wait for the lock and find the library. A lock
// that cannot be had (a file system without locks, or one held for too long) never hangs a run:
// the process then builds its own copy and renames it over, which is harmless.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

namespace cs {

struct RunPlan;
struct BlockResults;
using KernelFn = void (*)(const RunPlan&, BlockResults&);

// How the cache is named in messages about its trust (io/owned_directory.hpp).
inline constexpr const char* kKernelCachePurpose = "the kernel cache";

struct Toolchain {
  std::string compiler;              // $CONTACTSWEEP_CXX, else the program's own compiler
  std::vector<std::string> flags;    // the program's own, plus -fPIC -shared
  std::string include_dir;           // the headers' snapshot: installed, else the build tree's
  std::vector<std::string> system_include_dirs;  // MPI's
  std::vector<std::string> link_inputs;  // the Python module, when the kernel is built for it
};

Toolchain toolchain();

// Where kernels are cached. Throws InputError when there is no directory of this user's to use.
std::string kernel_cache_directory();

// The cache key of a kernel source (16 hex digits).
std::string kernel_key(const std::string& source);

struct BuiltKernel {
  std::string library;
  bool compiled = false;  // false: found in the cache
  double seconds = 0.0;   // compiling, when compiled
};

// Compiles `source` unless its library is cached and passes the checks. Throws
// std::runtime_error naming the compiler and its messages when the build fails, InputError
// when the cache cannot be trusted.
BuiltKernel build_kernel(const std::string& source);

// Checks the cached library of `source` and loads it (dlopen + dlsym of its entry point
// `entry`, kernel_source.hpp); throws std::runtime_error when it is missing, damaged, made for
// another key or without that entry point.
void* load_kernel(const std::string& source, const char* entry);

// Collective: one build per node (its first rank; the others wait), then every rank loads it
// and returns its entry point `entry`. Throws on every rank when any step fails anywhere.
// `beside`, if given, is the source of a kernel the run will load later (a basin map's orbit
// kernel): built into the cache at the same time, by a second compiler on another core, and
// not loaded; a failure there is left for the later build to report. *built_beside says
// whether it was compiled.
void* prepare_kernel(const std::string& source, const char* entry, MPI_Comm comm,
                     BuiltKernel* built = nullptr, const std::string* beside = nullptr,
                     BuiltKernel* built_beside = nullptr);

}  // namespace cs
