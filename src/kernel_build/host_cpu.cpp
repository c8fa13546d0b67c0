#include "kernel_build/host_cpu.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <string_view>

namespace cs {
namespace {

constexpr std::array<std::string_view, 10> kIdentityKeys = {
    "vendor_id",       "cpu family",       "model",       "model name", "flags",
    "CPU implementer", "CPU architecture", "CPU variant", "CPU part",   "Features"};

std::string_view trimmed(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

}  // namespace

std::string cpu_identity(std::istream& cpuinfo) {
  std::string identity;
  bool seen_processor = false;
  for (std::string line; std::getline(cpuinfo, line);) {
    const auto colon = line.find(':');
    const std::string_view key =
        trimmed(std::string_view(line).substr(0, std::min(colon, line.size())));
    if (key == "processor") {
      if (seen_processor) break;  // the second processor's block: the first one is complete
      seen_processor = true;
      continue;
    }
    if (colon == std::string::npos) continue;
    if (std::find(kIdentityKeys.begin(), kIdentityKeys.end(), key) == kIdentityKeys.end()) continue;
    identity += std::string(key) + ": " + std::string(trimmed(std::string_view(line).substr(colon + 1))) + "\n";
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
