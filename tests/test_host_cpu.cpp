// The CPU identity in the kernel cache's key (kernel_build/host_cpu.hpp): it must tell apart
// CPUs whose -march=native differs, and must not change with what varies on one machine (the
// clock, which core is read), or every run would rebuild its kernel.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "kernel_build/host_cpu.hpp"

namespace {

// Two processors of an x86 /proc/cpuinfo, as Linux writes it; `flags` and `mhz` vary.
std::string x86_cpuinfo(const std::string& flags, const std::string& mhz = "2596.128") {
  std::string block;
  for (int core = 0; core < 2; ++core) {
    block += "processor\t: " + std::to_string(core) + "\n";
    block += "vendor_id\t: AuthenticAMD\ncpu family\t: 25\nmodel\t\t: 17\n";
    block += "model name\t: AMD EPYC\nstepping\t: 1\n";
    block += "cpu MHz\t\t: " + (core == 0 ? mhz : std::string("1800.000")) + "\n";
    block += "core id\t\t: " + std::to_string(core) + "\n";
    block += "flags\t\t: " + flags + "\nbogomips\t: 5192.25\n\n";
  }
  return block;
}

std::string identity_of(const std::string& text) {
  std::istringstream in(text);
  return cs::cpu_identity(in);
}

const std::string kAvx512 = "fpu sse2 avx fma avx2 avx512f avx512dq avx512vl";
const std::string kAvx2 = "fpu sse2 avx fma avx2";

TEST(HostCpu, IdentityIsTheFirstProcessorsModelAndFlags) {
  EXPECT_EQ(identity_of(x86_cpuinfo(kAvx512)),
            "vendor_id: AuthenticAMD\ncpu family: 25\nmodel: 17\nmodel name: AMD EPYC\n"
            "flags: " + kAvx512 + "\n");
}

TEST(HostCpu, FewerInstructionsGiveAnotherIdentity) {
  EXPECT_NE(identity_of(x86_cpuinfo(kAvx512)), identity_of(x86_cpuinfo(kAvx2)));
}

TEST(HostCpu, ClockAndCoreDoNotChangeTheIdentity) {
  EXPECT_EQ(identity_of(x86_cpuinfo(kAvx2, "2596.128")), identity_of(x86_cpuinfo(kAvx2, "3700.000")));
}

TEST(HostCpu, ArmFieldsCount) {
  const std::string arm =
      "processor\t: 0\nBogoMIPS\t: 50.00\nFeatures\t: fp asimd sve\nCPU implementer\t: 0x41\n"
      "CPU architecture: 8\nCPU variant\t: 0x1\nCPU part\t: 0xd40\nCPU revision\t: 1\n\n";
  std::string without_sve = arm;
  without_sve.replace(without_sve.find(" sve"), 4, "");
  EXPECT_EQ(identity_of(arm),
            "Features: fp asimd sve\nCPU implementer: 0x41\nCPU architecture: 8\n"
            "CPU variant: 0x1\nCPU part: 0xd40\n");
  EXPECT_NE(identity_of(arm), identity_of(without_sve));
}

TEST(HostCpu, NoCpuinfoGivesAnEmptyIdentity) {
  EXPECT_EQ(identity_of(""), "");
  EXPECT_EQ(identity_of("no cpu here\n"), "");
}

TEST(HostCpu, ThisHostHasAnIdentity) {
#if defined(__linux__) && (defined(__x86_64__) || defined(__aarch64__))
  const std::string& identity = cs::host_cpu_identity();
  EXPECT_TRUE(identity.find("flags: ") != std::string::npos ||
              identity.find("Features: ") != std::string::npos)
      << identity;
  EXPECT_EQ(&identity, &cs::host_cpu_identity()) << "read once";
#else
  GTEST_SKIP() << "no /proc/cpuinfo format known here";
#endif
}

}  // namespace
