// Names shared by the spec parser's files (spec_parser.cpp and the files it is split into).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace cs::spec {

using Names = std::vector<std::string>;

// Source path given to the nodes parsed from a --set argument, so messages can name it.
inline constexpr std::string_view kSetPrefix = "--set ";

// The sections in the order spec_text writes them.
inline constexpr std::string_view kSections[] = {"scene", "initial", "integrator", "grid",
                                                 "measures"};

inline bool contains(const Names& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

inline std::string dotted(std::string_view prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : fmt::format("{}.{}", prefix, key);
}

}  // namespace cs::spec
