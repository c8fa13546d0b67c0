// How much memory a run may use: the smaller of the memory the machine has available and the
// headroom of every cgroup limit above this process (Slurm and containers set them; the memory of
// a big shared node says nothing about the job's share of it), unless CONTACTSWEEP_MEMORY_LIMIT
// is set, which replaces that figure in either direction: the user knows their allocation better
// than we can guess it. Runs that need more are refused before anything is allocated
// (spec_parser.cpp for the grid's coordinates, sweep.cpp for the results).
#pragma once

#include <cstdlib>
#include <string>

namespace cs {

// Where the figure is read from; the defaults are the real machine, tests point them at fake
// trees.
struct MemoryBudgetSources {
  std::string proc_root = "/proc";             // meminfo, self/cgroup
  std::string cgroup_root = "/sys/fs/cgroup";  // v2 mount; v1's memory controller is memory/
  const char* limit_env = std::getenv("CONTACTSWEEP_MEMORY_LIMIT");  // nullptr: unset
};

struct MemoryBudget {
  double bytes = 0.0;
  std::string source;  // which limit applied, for messages: "cgroup /sys/fs/cgroup/job_5 ..."
};

// CONTACTSWEEP_MEMORY_LIMIT is a whole number of bytes with an optional binary suffix K, M, G or
// T (e.g. 8G); a malformed value is an InputError naming it.
MemoryBudget memory_budget(const MemoryBudgetSources& sources = {});

// memory_budget().bytes.
double memory_budget_bytes();

}  // namespace cs
