// --set overrides: each argument parsed as one TOML key = value (a bare word as a string, whose
// quotes the shell ate), merged into the document, and the grid order kept.
#include "io/spec_overrides.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <utility>

#include "io/spec_text.hpp"
#include "model/run_spec.hpp"

namespace cs::spec {
namespace {

// toml::table iterates in key order, but the first grid axis varies slowest: recover file order.
Names keys_in_source_order(const toml::node* node) {
  std::vector<std::pair<toml::source_position, std::string>> keyed;
  if (const toml::table* t = node != nullptr ? node->as_table() : nullptr)
    for (const auto& [key, value] : *t) keyed.emplace_back(value.source().begin, key.str());
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  Names keys;
  for (auto& entry : keyed) keys.push_back(std::move(entry.second));
  return keys;
}

struct Override {
  std::string arg;     // as given, for messages
  Names path;          // the dotted key, split
  toml::table parsed;  // "KEY = VALUE" parsed: tables it creates carry the --set origin
};

std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  return std::string(text.substr(first, text.find_last_not_of(" \t") - first + 1));
}

Names split_key(const std::string& key, const std::string& arg) {
  Names path;
  std::size_t begin = 0;
  while (true) {
    const std::size_t dot = key.find('.', begin);
    path.push_back(key.substr(begin, dot - begin));
    if (!is_bare_key(path.back()))
      throw InputError(
          fmt::format("--set {}: '{}' is not a dotted key of plain names "
                      "(like integrator.h or grid.q_0.n)",
                      arg, key));
    if (dot == std::string::npos) return path;
    begin = dot + 1;
  }
}

// A word such as double_well: no TOML value, and clearly meant as a string whose quotes the
// shell removed.
bool is_bare_word(std::string_view value) {
  return is_bare_key(value) && std::isalpha(static_cast<unsigned char>(value.front()));
}

// "KEY = VALUE" must hold nothing but KEY: VALUE could smuggle in more keys ("1\nx = 2").
void check_single_value(const Override& edit) {
  const toml::table* level = &edit.parsed;
  for (const std::string& key : edit.path) {
    if (level->size() != 1)
      throw InputError(fmt::format("--set {}: the value must be a single TOML value", edit.arg));
    level = level->get(key)->as_table();  // nullptr at the value itself, ending the walk
    if (level == nullptr) return;
  }
}

Override parse_override(const std::string& arg) {
  const std::size_t eq = arg.find('=');
  if (eq == std::string::npos)
    throw InputError(
        fmt::format("--set {}: expected KEY=VALUE, e.g. --set integrator.h=0.005", arg));
  const std::string key = trimmed(std::string_view(arg).substr(0, eq));
  const std::string value = trimmed(std::string_view(arg).substr(eq + 1));
  if (key.empty()) throw InputError(fmt::format("--set {}: empty key before '='", arg));
  if (value.empty()) throw InputError(fmt::format("--set {}: empty value after '='", arg));
  Override result{arg, split_key(key, arg), {}};
  const std::string origin = std::string(kSetPrefix) + arg;
  try {
    result.parsed = toml::parse(key + " = " + value, origin);
  } catch (const toml::parse_error& error) {
    if (!is_bare_word(value))
      throw InputError(
          fmt::format("--set {}: {} is not a TOML value ({}); strings need quotes, "
                      "e.g. --set 'scene.name=\"double_well\"'",
                      arg, value, error.description()));
    result.parsed = toml::parse(key + " = " + toml_string(value), origin);
  }
  check_single_value(result);
  return result;
}

// Moving (not copying) keeps the node's source region, so messages can name the --set argument.
void move_into(toml::table& table, const std::string& key, toml::node& node) {
  node.visit([&](auto& value) { table.insert_or_assign(key, std::move(value)); });
}

void apply_override(toml::table& doc, Override& edit) {
  toml::table* target = &doc;
  toml::table* incoming = &edit.parsed;
  for (std::size_t i = 0; i < edit.path.size(); ++i) {
    const std::string& key = edit.path[i];
    toml::node* node = incoming->get(key);
    toml::node* existing = target->get(key);
    if (existing == nullptr || i + 1 == edit.path.size()) {
      move_into(*target, key, *node);
      return;
    }
    if (!existing->is_table())
      throw InputError(fmt::format(
          "--set {0}: '{1}' is {2} in the spec, not a table; set it whole (--set {1}=...)",
          edit.arg, fmt::join(edit.path.begin(), edit.path.begin() + i + 1, "."),
          type_name(*existing)));
    target = existing->as_table();
    incoming = node->as_table();
  }
}

// An axis keeps its place when --set changes it; a new axis comes last.
void update_grid_order(Names& order, const Names& path, const toml::table& doc) {
  if (path.front() != "grid") return;
  if (path.size() == 1) {
    order = keys_in_source_order(doc.get("grid"));
  } else if (!contains(order, path[1])) {
    order.push_back(path[1]);
  }
}

}  // namespace

Names apply_overrides(toml::table& doc, const std::vector<std::string>& overrides) {
  Names grid_order = keys_in_source_order(doc.get("grid"));
  for (const std::string& arg : overrides) {
    Override edit = parse_override(arg);
    apply_override(doc, edit);
    update_grid_order(grid_order, edit.path, doc);
  }
  return grid_order;
}

}  // namespace cs::spec
