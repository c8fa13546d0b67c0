#include "parallel/team_cpus.hpp"

#include <omp.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>

namespace cs {

std::vector<int> team_cpus() {
  std::vector<int> cpus;
  for (int place = 0; place < omp_get_num_places(); ++place) {
    std::vector<int> ids(static_cast<std::size_t>(omp_get_place_num_procs(place)));
    omp_get_place_proc_ids(place, ids.data());
    cpus.insert(cpus.end(), ids.begin(), ids.end());
  }
  std::sort(cpus.begin(), cpus.end());
  cpus.erase(std::unique(cpus.begin(), cpus.end()), cpus.end());
  return cpus;
}

CpuMask::CpuMask(const std::vector<int>& cpus) {
  int most = 0;
  for (const int cpu : cpus) most = std::max(most, cpu);
  // Sized for the highest CPU, as libgomp sizes its own: a fixed cpu_set_t holds CPU_SETSIZE
  // (1024) CPUs, and a team on a larger machine lost those above it (all of them: its own core).
  set_ = CPU_ALLOC(most + 1);
  if (set_ == nullptr) return;
  bytes_ = CPU_ALLOC_SIZE(most + 1);
  CPU_ZERO_S(bytes_, set_);
  for (const int cpu : cpus)
    if (cpu >= 0) CPU_SET_S(static_cast<std::size_t>(cpu), bytes_, set_);
}

CpuMask::~CpuMask() {
  if (set_ != nullptr) CPU_FREE(set_);
}

bool CpuMask::has(int cpu) const {
  return set_ != nullptr && cpu >= 0 && CPU_ISSET_S(static_cast<std::size_t>(cpu), bytes_, set_);
}

int CpuMask::count() const { return set_ == nullptr ? 0 : CPU_COUNT_S(bytes_, set_); }

void run_on_team_cpus() {
  const std::vector<int> cpus = team_cpus();
  if (cpus.empty()) return;
  const CpuMask mask(cpus);
  if (mask.count() == 0) return;
  pthread_setaffinity_np(pthread_self(), mask.bytes(), mask.set());
}

}  // namespace cs
