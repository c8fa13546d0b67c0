// The spec reader's entry and what every section shares: messages that name where a value came
// from (file position or --set argument), unknown keys with a suggestion, typed access.
#include "io/spec_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <string>

#include "io/spec_suggestions.hpp"
#include "io/spec_text.hpp"

namespace cs::spec {

RunSpec SpecReader::read() {
  check_keys(doc_, "", top_level_keys());
  read_scene();
  read_initial();
  read_integrator();
  read_grid();
  read_measures();
  check_adaptive_measures();
  read_title();
  return std::move(spec_);
}

std::string SpecReader::where(const toml::node* at) const {
  if (at == nullptr || !at->source().path) return source_name_;
  const std::string& path = *at->source().path;
  if (path.starts_with(kSetPrefix)) return path;
  return fmt::format("{}:{}:{}", path, at->source().begin.line, at->source().begin.column);
}

void SpecReader::fail(const toml::node* at, std::string_view message) const {
  throw InputError(fmt::format("{}: {}", where(at), message));
}

void SpecReader::fail_type(const toml::node& node, std::string_view key,
                            std::string_view expected) const {
  fail(&node,
       fmt::format("{}: expected {}, got {} {}", key, expected, type_name(node), shown(node)));
}

void SpecReader::fail_value(const toml::node& node, std::string_view key,
                             std::string_view expected) const {
  fail(&node, fmt::format("{} = {}: expected {}", key, shown(node), expected));
}

void SpecReader::check_keys(const toml::table& table, std::string_view prefix,
                            const Names& allowed) const {
  for (const auto& [key, node] : table) {
    if (contains(allowed, key.str())) continue;
    std::string hint = contact_variable_hint(key.str(), allowed, prefix);
    if (hint.empty()) hint = did_you_mean(key.str(), allowed, prefix);
    if (hint.empty()) hint = elsewhere_hint(key.str(), prefix);
    fail(&node,
         fmt::format("unknown key '{}'{}; valid {}: {}", dotted(prefix, key.str()), hint,
                     prefix.empty() ? "top-level keys" : fmt::format("keys in [{}]", prefix),
                     fmt::join(allowed, ", ")));
  }
}

std::string SpecReader::elsewhere_hint(std::string_view key, std::string_view prefix) const {
  for (const std::string& path : known_paths()) {
    const auto dot = path.rfind('.');
    if (path.substr(dot + 1) == key && path.substr(0, dot) != prefix)
      return fmt::format(" (did you mean '{}'?)", path);
  }
  return "";
}

Names SpecReader::known_paths() const {
  Names paths{"scene.name", "integrator.method", "integrator.h", "integrator.t_end"};
  if (scene_ == nullptr) return paths;
  for (const std::string& p : parameter_names(*scene_)) paths.push_back("scene." + p);
  for (const std::string& v : variable_names(*scene_)) paths.push_back("initial." + v);
  for (const std::string_view m : kMeasureNames) paths.push_back(fmt::format("measures.{}", m));
  return paths;
}

Names SpecReader::top_level_keys() {
  Names keys{"title"};
  for (const std::string_view section : kSections) keys.emplace_back(section);
  return keys;
}

double SpecReader::number(const toml::node& node, std::string_view key) const {
  double value = 0.0;
  if (const auto* i = node.as_integer())
    value = static_cast<double>(i->get());
  else if (const auto* f = node.as_floating_point())
    value = f->get();
  else
    fail_type(node, key, "a number");
  if (!std::isfinite(value)) fail_value(node, key, "a finite number");
  return value;
}

std::int64_t SpecReader::integer(const toml::node& node, std::string_view key) const {
  if (const auto* i = node.as_integer()) return i->get();
  fail_type(node, key, "an integer (a whole number without a decimal point)");
}

bool SpecReader::boolean(const toml::node& node, std::string_view key) const {
  if (const auto* b = node.as_boolean()) return b->get();
  fail_type(node, key, "true or false");
}

std::string SpecReader::string(const toml::node& node, std::string_view key) const {
  if (const auto* s = node.as_string()) {
    // TOML allows "\u0000"; HDF5 attributes and C strings would cut the text there.
    if (s->get().find('\0') != std::string::npos)
      fail(&node, fmt::format("{} contains a NUL character (\\u0000), which no attribute or "
                              "name can hold", key));
    return s->get();
  }
  fail_type(node, key, "a string (in quotes)");
}

const toml::table& SpecReader::table(const toml::node& node, std::string_view key) const {
  if (const auto* t = node.as_table()) return *t;
  fail_type(node, key, "a table");
}

const toml::array& SpecReader::array(const toml::node& node, std::string_view key) const {
  if (const auto* a = node.as_array()) return *a;
  fail_type(node, key, "an array [...]");
}

std::vector<double> SpecReader::numbers(const toml::node& node, std::string_view key) const {
  std::vector<double> values;
  const toml::array& items = array(node, key);
  for (std::size_t i = 0; i < items.size(); ++i)
    values.push_back(number(*items.get(i), fmt::format("{}[{}]", key, i)));
  return values;
}

const toml::table& SpecReader::section(std::string_view name) const {
  static const toml::table empty;
  const toml::node* node = doc_.get(name);
  return node == nullptr ? empty : table(*node, name);
}

double SpecReader::number_or(const toml::table& t, std::string_view prefix, std::string_view key,
                 double fallback) const {
  const toml::node* node = t.get(key);
  return node == nullptr ? fallback : number(*node, dotted(prefix, key));
}

}  // namespace cs::spec
