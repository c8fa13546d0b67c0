// Kernels of custom scenes, compiled once and kept: the generated source is compiled by the
// compiler and with the flags this program was built with into a shared object, cached under a
// hash of (source, compiler, flags, version, build, CPU) in $CONTACTSWEEP_CACHE, else
// $XDG_CACHE_HOME/contactsweep, else ~/.cache/contactsweep, and loaded with dlopen. The CPU is
// in the key when the flags say -march=native: a cache shared by machines of several kinds then
// keeps a kernel for each (host_cpu.hpp).
//
// Concurrent builders of the same kernel (ranks of a node, jobs sharing a home directory) build
// it once: the builder holds a lock on KEY.lock, compiles to a private name and renames the
// result into place atomically; the others wait for the lock and find the library. A lock that
// cannot be had (a file system without locks, or one held for too long) never hangs a run: the
// process then builds its own copy under its own name and renames it over, which is harmless.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

namespace cs {

struct RunPlan;
struct BlockResults;
using KernelFn = void (*)(const RunPlan&, BlockResults&);

struct Toolchain {
  std::string compiler;              // $CONTACTSWEEP_CXX, else the program's own compiler
  std::vector<std::string> flags;    // the program's own, plus -fPIC -shared
  std::string include_dir;           // the program's headers: installed, else the source tree
  std::vector<std::string> system_include_dirs;  // MPI's
};

Toolchain toolchain();

std::string kernel_cache_directory();

// The library a source compiles to (whether it exists yet or not).
std::string kernel_library_path(const std::string& source);

struct BuiltKernel {
  std::string library;
  bool compiled = false;  // false: found in the cache
  double seconds = 0.0;   // compiling, when compiled
};

// Compiles `source` unless its library is cached. Throws std::runtime_error naming the compiler
// and its messages when the build fails.
BuiltKernel build_kernel(const std::string& source);

// dlopen + dlsym of the entry point; throws std::runtime_error.
KernelFn load_kernel(const std::string& library);

// Collective: one build per node (its first rank; the others wait), then every rank loads it.
// Throws on every rank when any step fails anywhere.
KernelFn prepare_kernel(const std::string& source, MPI_Comm comm, BuiltKernel* built = nullptr);

}  // namespace cs
