// The journal writer's thread may run on every CPU of the OpenMP team, not on the initial
// thread's core alone (parallel/team_cpus.hpp). Run by CTest with OMP_PLACES=cores and
// OMP_PROC_BIND=close, the hybrid layout in which libgomp binds the initial thread to the first
// place and every std::thread it starts inherits that place.
#include <gtest/gtest.h>
#include <omp.h>
#include <sched.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <thread>
#include <vector>

#include "parallel/journal.hpp"
#include "parallel/journal_writer.hpp"
#include "parallel/run_identity.hpp"
#include "parallel/team_cpus.hpp"
#include "support/private_temp_dir.hpp"

namespace cs {
namespace {

std::set<int> my_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return {};
  std::set<int> cpus;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
    if (CPU_ISSET(cpu, &set)) cpus.insert(cpu);
  return cpus;
}

// The team's CPUs as libgomp binds them: one thread per place, each reading its own mask
// (independent of omp_get_place_proc_ids, which team_cpus() reads).
std::set<int> cpus_the_team_is_bound_to() {
  std::set<int> all;
#pragma omp parallel num_threads(omp_get_num_places()) proc_bind(spread)
  {
    const std::set<int> mine = my_cpus();
#pragma omp critical
    all.insert(mine.begin(), mine.end());
  }
  return all;
}

TEST(TeamCpus, JournalWriterRunsOnEveryCpuOfTheTeam) {
  if (omp_get_num_places() < 2)
    GTEST_SKIP() << "needs OMP_PLACES with at least 2 places (2 cores): " << omp_get_num_places();
  const std::set<int> team = cpus_the_team_is_bound_to();
  ASSERT_GE(team.size(), 2u);
  // The trap: the initial thread is bound to one place, and a thread it starts inherits it.
  std::set<int> inherited;
  std::thread([&] { inherited = my_cpus(); }).join();
  EXPECT_LT(inherited.size(), team.size()) << "the initial thread was not bound: the test sees nothing";

  const std::vector<int> cpus = team_cpus();
  const std::set<int> listed(cpus.begin(), cpus.end());
  EXPECT_EQ(listed, team);

  test::PrivateTempDir temp("contactsweep_team_cpus_");
  const std::string output = (temp.path() / "out.h5").string();
  Journal journal(output, "00000000000000aa");
  journal.lock();
  journal.start({"00000000000000aa", build_identity(), 10, 10, false, "[scene]\nname = \"double_well\"\n"});
  DatasetSpec final_q;
  final_q.name = "final_q";
  BlockResults block({0, 10}, {{final_q, 1}});
  std::set<int> writer_cpus;
  {
    JournalWriter writer(journal, [&](std::int64_t) { writer_cpus = my_cpus(); }, [] {});
    writer.submit(block);
    writer.finish();
  }
  EXPECT_EQ(writer_cpus, team) << "the writer's thread is held to " << writer_cpus.size()
                               << " of the team's " << team.size() << " CPUs";
}

// A machine with more than 1024 CPUs (CPU_SETSIZE, cpu_set_t's fixed size): a team there on
// CPUs 1024 and above lost them from the writer's mask, all of them where the team had no lower
// one (the writer then kept thread 0's core). Not seen on this machine's CPUs: the mask alone.
TEST(TeamCpus, MaskHoldsCpusAboveCpuSetSize) {
  const int high = CPU_SETSIZE + 476;
  const CpuMask mask({3, high});
  EXPECT_TRUE(mask.has(3));
  EXPECT_TRUE(mask.has(high));
  EXPECT_FALSE(mask.has(4));
  EXPECT_FALSE(mask.has(high - 1));
  EXPECT_EQ(mask.count(), 2);
  EXPECT_GE(mask.bytes() * 8, static_cast<std::size_t>(high) + 1);
  const CpuMask only_high({CPU_SETSIZE, CPU_SETSIZE + 1});
  EXPECT_EQ(only_high.count(), 2);
}

}  // namespace
}  // namespace cs
