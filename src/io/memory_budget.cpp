#include "io/memory_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>

#include "io/run_spec.hpp"

namespace cs {
namespace {

double free_physical_memory() {
  return static_cast<double>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// cgroup v2 memory.max minus memory.current, if this process runs under a numeric limit
// ("max" means none).
double cgroup_headroom() {
  auto read_number = [](const char* path) -> double {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text)) return -1.0;
    std::uint64_t value = 0;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() ? static_cast<double>(value)
                                                                    : -1.0;
  };
  const double limit = read_number("/sys/fs/cgroup/memory.max");
  if (limit < 0) return -1.0;
  return std::max(0.0, limit - std::max(0.0, read_number("/sys/fs/cgroup/memory.current")));
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

double memory_budget_bytes() {
  double budget = free_physical_memory();
  if (const double headroom = cgroup_headroom(); headroom >= 0) budget = std::min(budget, headroom);
  if (const char* limit = std::getenv("CONTACTSWEEP_MEMORY_LIMIT"))
    budget = std::min(budget, parse_limit(limit));
  return budget;
}

}  // namespace cs
