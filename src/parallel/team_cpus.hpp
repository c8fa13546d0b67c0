// Where a helper thread of the run (the journal writer) may run: on every CPU of the OpenMP
// team's places, not on the initial thread's alone.
//
// Under OMP_PROC_BIND with OMP_PLACES (the hybrid layout of docs/scale.md, and
// jobs/bench_basins.sh), libgomp binds the initial thread to the first place when it starts,
// and a std::thread started from it inherits that one place. The journal writer then shared
// OpenMP thread 0's core with it, while thread 0 also streams the output: the 512² map with the
// early stop took 0.224 s bound against 0.194 s unbound. Allowed on every place, the writer
// takes whichever core is free, as it does when nothing is bound: 0.193 s bound (2 threads,
// medians of 22 interleaved runs, AMD EPYC Zen 5; integrated to t_end, 0.414 -> 0.409 s).
#pragma once

#include <sched.h>

#include <cstddef>
#include <vector>

namespace cs {

// The CPUs of every OpenMP place, ascending; empty when there are no places (nothing bound).
std::vector<int> team_cpus();

// A CPU set sized for its highest CPU (CPU_ALLOC), not cpu_set_t's fixed 1024.
class CpuMask {
 public:
  explicit CpuMask(const std::vector<int>& cpus);
  ~CpuMask();
  CpuMask(const CpuMask&) = delete;
  CpuMask& operator=(const CpuMask&) = delete;
  bool has(int cpu) const;
  int count() const;
  std::size_t bytes() const { return bytes_; }
  const cpu_set_t* set() const { return set_; }

 private:
  cpu_set_t* set_ = nullptr;
  std::size_t bytes_ = 0;
};

// Lets the calling thread run on team_cpus(). Without places, or where the system refuses,
// it leaves the thread as it is: the thread runs either way, only where differs.
void run_on_team_cpus();

}  // namespace cs
