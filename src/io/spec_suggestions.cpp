// "Did you mean": aliases from other tools, initial value and grid axis (q, q_0), edit distance.
#include "io/spec_suggestions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace cs::spec {
namespace {

// Names users bring from other tools, which edit distance alone would not find.
// clang-format off
constexpr std::pair<std::string_view, std::string_view> kAliases[] = {
    {"dt", "h"}, {"step", "h"}, {"stepsize", "h"}, {"step_size", "h"}, {"timestep", "h"},
    {"time_step", "h"}, {"tmax", "t_end"}, {"t_max", "t_end"}, {"tfinal", "t_end"},
    {"t_final", "t_end"}, {"duration", "t_end"}, {"scheme", "method"}, {"integrator", "method"},
    {"algorithm", "method"}, {"model", "name"}, {"start", "from"}, {"stop", "to"}, {"end", "to"},
    {"num", "n"}, {"count", "n"}, {"points", "n"}, {"list", "values"}, {"stride", "every"},
    {"interval", "every"}, {"variables", "vars"}, {"final", "final_state"},
    {"traj", "trajectory"}, {"synchronization", "sync"}, {"basins", "basin"}};
// clang-format on

// Optimal string alignment distance: Levenshtein plus adjacent transpositions ("t_ned").
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// The candidate the user most likely meant, if any is close enough to be worth suggesting.
std::optional<std::string> closest(std::string_view key, const Names& candidates) {
  for (const auto& [alias, target] : kAliases)
    if (key == alias && contains(candidates, target)) return std::string(target);
  // An initial value and its grid axis differ only by "_0" (q <-> q_0).
  if (key.ends_with("_0") && contains(candidates, key.substr(0, key.size() - 2)))
    return std::string(key.substr(0, key.size() - 2));
  if (contains(candidates, std::string(key) + "_0")) return std::string(key) + "_0";
  // About one typo per three characters, and never a suggestion that shares nothing with key.
  const std::size_t limit = std::max<std::size_t>(1, key.size() / 3);
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(key, candidate);
    if (distance < best_distance && distance < key.size()) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

// `key` with its word "s" (whole, or a part between underscores) spelled z: "" if it has none.
std::string with_z_for_s(std::string_view key) {
  std::string out;
  bool found = false;
  std::size_t begin = 0;
  while (begin <= key.size()) {
    const std::size_t end = std::min(key.find('_', begin), key.size());
    const std::string_view part = key.substr(begin, end - begin);
    if (begin > 0) out += '_';
    if (part == "s") {
      out += 'z';
      found = true;
    } else {
      out += part;
    }
    begin = end + 1;
  }
  return found ? out : "";
}

}  // namespace

std::string contact_variable_hint(std::string_view key, const Names& candidates,
                                  std::string_view prefix) {
  const std::string z_name = with_z_for_s(key);
  if (z_name.empty()) return "";
  const std::string note = "contactsweep calls it z (z = −s)";
  if (contains(candidates, z_name))
    return fmt::format(" ({}, so its value changes sign: did you mean '{}'?)", note,
                       dotted(prefix, z_name));
  return fmt::format(" ({})", note);
}

std::string did_you_mean(std::string_view key, const Names& candidates, std::string_view prefix) {
  const auto near = closest(key, candidates);
  return near ? fmt::format(" (did you mean '{}'?)", dotted(prefix, *near)) : "";
}

}  // namespace cs::spec
