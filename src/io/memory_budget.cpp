#include "io/memory_budget.hpp"

#include <unistd.h>

#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

#include "model/run_spec.hpp"

namespace cs {
namespace {

namespace fs = std::filesystem;

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g GiB", bytes / (1024.0 * 1024 * 1024));
  return text;
}

// The whole first word of a file as a number of bytes; nothing for "max" or a missing file.
std::optional<std::uint64_t> read_number(const fs::path& file) {
  std::ifstream in(file);
  std::string text;
  if (!(in >> text)) return std::nullopt;
  std::uint64_t value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// MemAvailable counts the page cache the kernel would drop for us; MemFree does not, so on a
// node that has been reading files it refuses runs that fit. Kernels before 3.14 lack it.
MemoryBudget available_memory(const fs::path& proc_root) {
  const fs::path meminfo = proc_root / "meminfo";
  std::ifstream in(meminfo);
  constexpr std::string_view kKey = "MemAvailable:";
  for (std::string line; std::getline(in, line);) {
    std::uint64_t kib = 0;
    if (line.starts_with(kKey) && std::istringstream(line.substr(kKey.size())) >> kib) {
      const double bytes = static_cast<double>(kib) * 1024.0;
      return {bytes, "MemAvailable " + gib(bytes)};
    }
  }
  const double bytes =
      static_cast<double>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  return {bytes, "free memory " + gib(bytes) + " (no MemAvailable in " + meminfo.string() + ")"};
}

// The files holding a cgroup's limit and the usage charged against it.
struct CgroupFiles {
  const char* limit;
  const char* usage;
};
constexpr CgroupFiles kV1{"memory.limit_in_bytes", "memory.usage_in_bytes"};
constexpr CgroupFiles kV2{"memory.max", "memory.current"};

// v2 writes "no limit" as "max", v1 as the largest page count in bytes (9223372036854771712).
constexpr std::uint64_t kUnlimited = std::uint64_t{1} << 60;

// The unused part of one cgroup's limit, if it has one.
std::optional<MemoryBudget> headroom(const fs::path& dir, const CgroupFiles& files) {
  const auto limit = read_number(dir / files.limit);
  if (!limit || *limit >= kUnlimited) return std::nullopt;
  const std::uint64_t usage = read_number(dir / files.usage).value_or(0);
  const double bytes = usage < *limit ? static_cast<double>(*limit - usage) : 0.0;
  return MemoryBudget{bytes, "cgroup " + dir.string() + " limit " +
                                 gib(static_cast<double>(*limit)) + ", " + gib(bytes) + " unused"};
}

void keep_tighter(std::optional<MemoryBudget>& tightest, std::optional<MemoryBudget> candidate) {
  if (candidate && (!tightest || candidate->bytes < tightest->bytes))
    tightest = std::move(candidate);
}

// Every level from the process's cgroup up to the mount root counts: Slurm sets the job's limit
// on the job's cgroup and runs each step in a child without one. Under a cgroup namespace or a
// container's private mount, the path the kernel reports may not exist below the mount (its
// levels then have no files to read) or may leave it ("/../x"); the mount root, the container's
// own cgroup, is read in any case.
std::optional<MemoryBudget> tightest_limit(const fs::path& mount, const std::string& cgroup,
                                           const CgroupFiles& files) {
  fs::path relative = fs::path(cgroup).relative_path().lexically_normal();
  if (!relative.empty() && *relative.begin() == "..") relative.clear();
  std::optional<MemoryBudget> tightest;
  for (fs::path level = relative; !level.empty(); level = level.parent_path())
    keep_tighter(tightest, headroom(mount / level, files));
  keep_tighter(tightest, headroom(mount, files));
  return tightest;
}

bool lists_memory(std::string_view controllers) {
  while (!controllers.empty()) {
    const auto comma = controllers.find(',');
    if (controllers.substr(0, comma) == "memory") return true;
    controllers.remove_prefix(comma == std::string_view::npos ? controllers.size() : comma + 1);
  }
  return false;
}

// The tightest limit over the process's own cgroups, from /proc/self/cgroup
// ("hierarchy:controllers:path" a line): v2's line is "0::path", v1's memory hierarchy lists
// "memory" among its controllers (mounted at memory/). Hybrid systems have both.
std::optional<MemoryBudget> cgroup_limit(const fs::path& proc_root, const fs::path& cgroup_root) {
  std::optional<MemoryBudget> tightest;
  std::ifstream in(proc_root / "self" / "cgroup");
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find(':');
    const auto second = first == std::string::npos ? first : line.find(':', first + 1);
    if (second == std::string::npos) continue;
    const std::string_view controllers(line.data() + first + 1, second - first - 1);
    const std::string path = line.substr(second + 1);
    if (line.starts_with("0::"))
      keep_tighter(tightest, tightest_limit(cgroup_root, path, kV2));
    else if (lists_memory(controllers))
      keep_tighter(tightest, tightest_limit(cgroup_root / "memory", path, kV1));
  }
  return tightest;
}

double parse_limit(std::string_view text) {
  std::uint64_t value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  std::string_view suffix(end, text.data() + text.size());
  double scale = 1.0;
  if (suffix.size() == 1) {
    constexpr std::string_view kSuffixes = "KMGT";
    const auto position = kSuffixes.find(static_cast<char>(std::toupper(suffix[0])));
    if (position != std::string_view::npos) {
      scale = static_cast<double>(std::uint64_t{1} << (10 * (position + 1)));
      suffix.remove_prefix(1);
    }
  }
  if (error != std::errc() || end == text.data() || !suffix.empty() || value == 0)
    throw InputError("CONTACTSWEEP_MEMORY_LIMIT='" + std::string(text) +
                     "': expected a whole number of bytes > 0 with an optional suffix K, M, G "
                     "or T (e.g. 8G)");
  return static_cast<double>(value) * scale;
}

}  // namespace

MemoryBudget memory_budget(const MemoryBudgetSources& sources) {
  if (sources.limit_env)
    return {parse_limit(sources.limit_env),
            std::string("CONTACTSWEEP_MEMORY_LIMIT=") + sources.limit_env};
  const MemoryBudget node = available_memory(sources.proc_root);
  const auto cgroup = cgroup_limit(sources.proc_root, sources.cgroup_root);
  if (!cgroup || cgroup->bytes >= node.bytes) return node;
  return {cgroup->bytes, cgroup->source + " (node: " + node.source + ")"};
}

double memory_budget_bytes() { return memory_budget().bytes; }

}  // namespace cs
