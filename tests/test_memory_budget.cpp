// The memory budget on fake /proc and /sys/fs/cgroup trees: MemAvailable rather than MemFree, the
// process's own cgroup (v2 and v1, every level up to the mount root, the mount root when the
// path is namespaced away), and CONTACTSWEEP_MEMORY_LIMIT replacing the figure either way.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "io/memory_budget.hpp"
#include "model/run_spec.hpp"
#include "support/private_temp_dir.hpp"

namespace cs {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kKiB = 1024;
constexpr std::uint64_t kMiB = 1024 * kKiB;
constexpr std::uint64_t kGiB = 1024 * kMiB;

class MemoryBudgetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A fresh private directory (mkdtemp): a guessable name in a shared /tmp may be another
    // user's, and the test removes its directory at the end.
    temp_ = std::make_unique<test::PrivateTempDir>("contactsweep_memory_budget_");
    root_ = temp_->path();
    // MemFree far below MemAvailable, as on a node whose memory is mostly page cache.
    write("proc/meminfo",
          "MemTotal:       67108864 kB\n"
          "MemFree:           65536 kB\n"
          "MemAvailable:   16777216 kB\n"
          "Cached:         50331648 kB\n"
          "HugePages_Total:       0\n");
  }
  void TearDown() override { temp_.reset(); }

  void write(const fs::path& relative, const std::string& text) {
    fs::create_directories((root_ / relative).parent_path());
    std::ofstream(root_ / relative) << text;
  }
  void own_cgroup(const std::string& lines) { write("proc/self/cgroup", lines); }
  void v2_level(const std::string& dir, const std::string& max, std::uint64_t current) {
    write("cgroup/" + dir + "/memory.max", max + "\n");
    write("cgroup/" + dir + "/memory.current", std::to_string(current) + "\n");
  }
  void v1_level(const std::string& dir, std::uint64_t limit, std::uint64_t usage) {
    write("cgroup/memory/" + dir + "/memory.limit_in_bytes", std::to_string(limit) + "\n");
    write("cgroup/memory/" + dir + "/memory.usage_in_bytes", std::to_string(usage) + "\n");
  }
  MemoryBudget budget(const char* limit_env = nullptr) const {
    return memory_budget({(root_ / "proc").string(), (root_ / "cgroup").string(), limit_env});
  }
  std::string cgroup_dir(const std::string& relative) const {
    return (root_ / "cgroup" / relative).string();
  }

  std::unique_ptr<test::PrivateTempDir> temp_;
  fs::path root_;
  static constexpr double kMemAvailable = 16.0 * kGiB;  // 16777216 kB
};

TEST_F(MemoryBudgetTest, UsesMemAvailableNotMemFree) {
  own_cgroup("0::/\n");
  const MemoryBudget result = budget();
  EXPECT_EQ(result.bytes, kMemAvailable);
  EXPECT_EQ(result.source, "MemAvailable 16 GiB");
}

TEST_F(MemoryBudgetTest, FallsBackToFreePagesWithoutMemAvailable) {
  write("proc/meminfo", "MemTotal:       67108864 kB\nMemFree:           65536 kB\n");
  own_cgroup("0::/\n");
  const MemoryBudget result = budget();
  EXPECT_GT(result.bytes, 0.0);
  EXPECT_EQ(result.source.rfind("free memory ", 0), 0u) << result.source;
}

// Slurm: the job's cgroup carries the limit, the step below it has none.
TEST_F(MemoryBudgetTest, V2JobLimitAppliesToStepBelowIt) {
  own_cgroup("0::/system.slice/slurmstepd.scope/job_5/step_0\n");
  v2_level("system.slice", "max", 40 * kGiB);
  v2_level("system.slice/slurmstepd.scope/job_5", std::to_string(4 * kGiB), 1 * kGiB);
  v2_level("system.slice/slurmstepd.scope/job_5/step_0", "max", 1 * kGiB);
  const MemoryBudget result = budget();
  EXPECT_EQ(result.bytes, 3.0 * kGiB);
  EXPECT_EQ(result.source, "cgroup " + cgroup_dir("system.slice/slurmstepd.scope/job_5") +
                               " limit 4 GiB, 3 GiB unused (node: MemAvailable 16 GiB)");
}

TEST_F(MemoryBudgetTest, V2TighterStepLimitWinsOverJob) {
  own_cgroup("0::/slurm/job_5/step_0\n");
  v2_level("slurm/job_5", std::to_string(4 * kGiB), 1 * kGiB);            // 3 GiB unused
  v2_level("slurm/job_5/step_0", std::to_string(2560 * kMiB), 1 * kGiB);  // 1.5 GiB unused
  EXPECT_EQ(budget().bytes, 1.5 * kGiB);
}

TEST_F(MemoryBudgetTest, V2MemAvailableWinsOverLooseLimit) {
  own_cgroup("0::/slurm/job_5/step_0\n");
  v2_level("slurm/job_5", std::to_string(64 * kGiB), 1 * kGiB);
  v2_level("slurm/job_5/step_0", "max", 1 * kGiB);
  const MemoryBudget result = budget();
  EXPECT_EQ(result.bytes, kMemAvailable);
  EXPECT_EQ(result.source, "MemAvailable 16 GiB");
}

TEST_F(MemoryBudgetTest, V2UsageAboveLimitLeavesNothing) {
  own_cgroup("0::/job\n");
  v2_level("job", std::to_string(1 * kGiB), 1 * kGiB + 4096);
  EXPECT_EQ(budget().bytes, 0.0);
}

TEST_F(MemoryBudgetTest, V2MaxEverywhereMeansNoLimit) {
  own_cgroup("0::/user.slice/session-1.scope\n");
  v2_level("user.slice", "max", 8 * kGiB);
  v2_level("user.slice/session-1.scope", "max", 1 * kGiB);
  EXPECT_EQ(budget().bytes, kMemAvailable);
}

// A container without a cgroup namespace sees the host's path, but its own cgroup is the mount.
TEST_F(MemoryBudgetTest, V2NamespacedPathFallsBackToMountRoot) {
  own_cgroup("0::/kubepods/burstable/pod1234/abcdef\n");
  v2_level(".", std::to_string(2 * kGiB), 512 * kMiB);
  const MemoryBudget result = budget();
  EXPECT_EQ(result.bytes, 1.5 * kGiB);
  EXPECT_EQ(result.source, "cgroup " + (root_ / "cgroup").string() +
                               " limit 2 GiB, 1.5 GiB unused (node: MemAvailable 16 GiB)");
}

// Outside the cgroup namespace's root the kernel reports "/../x": nothing above the mount counts.
TEST_F(MemoryBudgetTest, V2PathLeavingTheMountReadsOnlyMountRoot) {
  own_cgroup("0::/../sibling\n");
  write("memory.max", std::to_string(1 * kMiB) + "\n");  // the mount's parent: never read
  write("sibling/memory.max", std::to_string(1 * kMiB) + "\n");
  v2_level(".", std::to_string(2 * kGiB), 512 * kMiB);
  EXPECT_EQ(budget().bytes, 1.5 * kGiB);
}

TEST_F(MemoryBudgetTest, V1UnlimitedMeansNoLimit) {
  own_cgroup("5:cpu,cpuacct:/slurm/uid_0/job_12\n4:memory:/slurm/uid_0/job_12\n0::/\n");
  constexpr std::uint64_t kV1Unlimited = 9223372036854771712u;
  v1_level(".", kV1Unlimited, 30 * kGiB);
  v1_level("slurm/uid_0", kV1Unlimited, 2 * kGiB);
  v1_level("slurm/uid_0/job_12", kV1Unlimited, 1 * kGiB);
  EXPECT_EQ(budget().bytes, kMemAvailable);
}

TEST_F(MemoryBudgetTest, V1LimitAppliesFromAnyLevel) {
  own_cgroup("5:cpu,cpuacct:/slurm/uid_0/job_12/step_0\n4:memory:/slurm/uid_0/job_12/step_0\n");
  constexpr std::uint64_t kV1Unlimited = 9223372036854771712u;
  v1_level(".", kV1Unlimited, 30 * kGiB);
  v1_level("slurm/uid_0/job_12", 6 * kGiB, 2 * kGiB);
  v1_level("slurm/uid_0/job_12/step_0", kV1Unlimited, 1 * kGiB);
  const MemoryBudget result = budget();
  EXPECT_EQ(result.bytes, 4.0 * kGiB);
  EXPECT_EQ(result.source, "cgroup " + cgroup_dir("memory/slurm/uid_0/job_12") +
                               " limit 6 GiB, 4 GiB unused (node: MemAvailable 16 GiB)");
}

// The memory controller may share a hierarchy with others ("cpu,memory,hugetlb").
TEST_F(MemoryBudgetTest, V1NamespacedPathFallsBackToMountRoot) {
  own_cgroup("4:cpu,memory,hugetlb:/docker/0123abcd\n");
  v1_level(".", 3 * kGiB, 1 * kGiB);
  EXPECT_EQ(budget().bytes, 2.0 * kGiB);
}

TEST_F(MemoryBudgetTest, LimitEnvRaisesBudgetAboveMemAvailableAndCgroup) {
  own_cgroup("0::/job\n");
  v2_level("job", std::to_string(2 * kGiB), 0);
  const MemoryBudget result = budget("64G");
  EXPECT_EQ(result.bytes, 64.0 * kGiB);
  EXPECT_EQ(result.source, "CONTACTSWEEP_MEMORY_LIMIT=64G");
}

TEST_F(MemoryBudgetTest, LimitEnvLowersBudget) {
  own_cgroup("0::/\n");
  EXPECT_EQ(budget("512M").bytes, 512.0 * kMiB);
  EXPECT_EQ(budget("3k").bytes, 3.0 * kKiB);
  EXPECT_EQ(budget("1T").bytes, 1024.0 * kGiB);
  EXPECT_EQ(budget("1000").bytes, 1000.0);
}

TEST_F(MemoryBudgetTest, MalformedLimitEnvIsInputErrorNamingIt) {
  own_cgroup("0::/\n");
  for (const char* value : {"", "12X", "0", "-5", "8GB"}) {
    try {
      budget(value);
      ADD_FAILURE() << "no InputError for '" << value << "'";
    } catch (const InputError& error) {
      EXPECT_NE(
          std::string(error.what()).find("CONTACTSWEEP_MEMORY_LIMIT='" + std::string(value) + "'"),
          std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace cs
