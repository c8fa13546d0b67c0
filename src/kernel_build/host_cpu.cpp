#include "kernel_build/host_cpu.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <string_view>
#include <vector>

namespace cs {
namespace {

constexpr std::array<std::string_view, 15> kIdentityFields = {
    "vendor_id",        "cpu family",  "model",    "model name", "flags", "CPU implementer",
    "CPU architecture", "CPU variant", "CPU part", "Features",   "cpu",   "features",
    "facilities",       "isa",         "uarch"};

std::string_view trimmed(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

}  // namespace

std::string cpu_identity(std::istream& cpuinfo) {
  // The first occurrence of each field: on x86 all of them are in the first processor's block;
  // 32-bit Arm lists Features and the CPU part after the blocks.
  std::string identity;
  std::vector<std::string_view> seen;
  for (std::string line; std::getline(cpuinfo, line);) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string_view field = trimmed(std::string_view(line).substr(0, colon));
    const auto known = std::find(kIdentityFields.begin(), kIdentityFields.end(), field);
    if (known == kIdentityFields.end()) continue;
    if (std::find(seen.begin(), seen.end(), *known) != seen.end()) continue;
    seen.push_back(*known);
    identity += std::string(field) + ": ";
    identity += trimmed(std::string_view(line).substr(colon + 1));
    identity += '\n';
  }
  return identity;
}

const std::string& host_cpu_identity() {
  static const std::string identity = [] {
    std::ifstream in("/proc/cpuinfo");
    return in ? cpu_identity(in) : std::string();
  }();
  return identity;
}

}  // namespace cs
