// The CPU identity in the kernel cache's key (kernel_build/host_cpu.hpp): it must tell apart
// CPUs whose -march=native differs, and must not change with what varies on one machine (the
// clock, which core is read first), or every run would rebuild its kernel.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "kernel_build/host_cpu.hpp"

namespace {

// Two processors of an x86 /proc/cpuinfo, as Linux writes it. `flags` is both processors',
// `mhz` and `first_core` the first one's clock and core id.
std::string x86_cpuinfo(const std::string& flags, const std::string& mhz = "2596.128",
                        int first_core = 0) {
  std::string text;
  for (int processor = 0; processor < 2; ++processor) {
    const int core = processor == 0 ? first_core : first_core + 1;
    text += "processor\t: " + std::to_string(processor) + "\n";
    text += "vendor_id\t: AuthenticAMD\ncpu family\t: 25\nmodel\t\t: 17\n";
    text += "model name\t: AMD EPYC\nstepping\t: 1\n";
    text += "cpu MHz\t\t: " + (processor == 0 ? mhz : std::string("1800.000")) + "\n";
    text += "core id\t\t: " + std::to_string(core) + "\napicid\t\t: " + std::to_string(core) + "\n";
    text += "flags\t\t: " + flags + "\nbogomips\t: 5192.25\n\n";
  }
  return text;
}

std::string identity_of(const std::string& text) {
  std::istringstream in(text);
  return cs::cpu_identity(in);
}

const std::string kAvx512 = "fpu sse2 avx fma avx2 avx512f avx512dq avx512vl";
const std::string kAvx2 = "fpu sse2 avx fma avx2";

TEST(HostCpu, IdentityIsTheModelAndFlags) {
  EXPECT_EQ(identity_of(x86_cpuinfo(kAvx512)),
            "vendor_id: AuthenticAMD\ncpu family: 25\nmodel: 17\nmodel name: AMD EPYC\n"
            "flags: " +
                kAvx512 + "\n");
}

TEST(HostCpu, FewerInstructionsGiveAnotherIdentity) {
  EXPECT_NE(identity_of(x86_cpuinfo(kAvx512)), identity_of(x86_cpuinfo(kAvx2)));
}

TEST(HostCpu, ClockAndCoreDoNotChangeTheIdentity) {
  const std::string identity = identity_of(x86_cpuinfo(kAvx2, "2596.128", 0));
  EXPECT_EQ(identity, identity_of(x86_cpuinfo(kAvx2, "3700.000", 0)));
  EXPECT_EQ(identity, identity_of(x86_cpuinfo(kAvx2, "2596.128", 6)));
}

// 64-bit Arm lists every field per processor; 32-bit Arm lists Features and the CPU part once,
// after the processors' blocks.
TEST(HostCpu, ArmFieldsWhereverTheyAre) {
  const std::string arm64 =
      "processor\t: 0\nBogoMIPS\t: 50.00\nFeatures\t: fp asimd sve\nCPU implementer\t: 0x41\n"
      "CPU architecture: 8\nCPU variant\t: 0x1\nCPU part\t: 0xd40\nCPU revision\t: 1\n\n";
  const std::string expected =
      "Features: fp asimd sve\nCPU implementer: 0x41\nCPU architecture: 8\nCPU variant: 0x1\n"
      "CPU part: 0xd40\n";
  EXPECT_EQ(identity_of(arm64), expected);
  std::string without_sve = arm64;
  without_sve.replace(without_sve.find(" sve"), 4, "");
  EXPECT_NE(identity_of(arm64), identity_of(without_sve));

  const std::string arm32 =
      "processor\t: 0\nmodel name\t: ARMv7 Processor rev 4 (v7l)\nBogoMIPS\t: 38.40\n\n"
      "processor\t: 1\nmodel name\t: ARMv7 Processor rev 4 (v7l)\nBogoMIPS\t: 38.40\n\n"
      "Features\t: half thumb fastmult vfp neon vfpv4\nCPU implementer\t: 0x41\n"
      "CPU architecture: 7\nCPU variant\t: 0x0\nCPU part\t: 0xd03\nHardware\t: BCM2835\n";
  EXPECT_EQ(
      identity_of(arm32),
      "model name: ARMv7 Processor rev 4 (v7l)\nFeatures: half thumb fastmult vfp neon vfpv4\n"
      "CPU implementer: 0x41\nCPU architecture: 7\nCPU variant: 0x0\nCPU part: 0xd03\n");
}

TEST(HostCpu, NoCpuinfoGivesAnEmptyIdentity) {
  EXPECT_EQ(identity_of(""), "");
  EXPECT_EQ(identity_of("no cpu here\nprocessor\t: 0\ncpu MHz\t: 1000\n"), "");
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
