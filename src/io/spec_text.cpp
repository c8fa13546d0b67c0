// TOML as text: values inline, and the canonical spec_text.
#include "io/spec_text.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <sstream>

namespace cs::spec {
namespace {

// spec_text writes these keys first, in this order, wherever they occur; the rest by name.
constexpr std::string_view kLeadKeys[] = {"name", "method", "h", "t_end", "from", "to", "n"};

Names keys_in_written_order(const toml::table& table) {
  Names keys;
  for (const std::string_view lead : kLeadKeys)
    if (table.contains(lead)) keys.emplace_back(lead);
  for (const auto& [key, value] : table)
    if (!contains(keys, key.str())) keys.emplace_back(key.str());
  return keys;
}

std::string key_text(std::string_view key) {
  return is_bare_key(key) ? std::string(key) : toml_string(key);
}

// Shortest text that reads back to the same double (std::to_chars), kept a TOML float.
std::string float_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";  // "3" would read as integer
  return text;
}

}  // namespace

bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-';
  });
}

std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + '"';
}

// A value in TOML's one-line syntax: used for spec_text and to show values in messages.
std::string inline_toml(const toml::node& node) {
  if (const auto* s = node.as_string()) return toml_string(s->get());
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return float_text(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = node.as_array()) {
    Names items;
    for (const toml::node& item : *a) items.push_back(inline_toml(item));
    return fmt::format("[{}]", fmt::join(items, ", "));
  }
  if (const auto* t = node.as_table()) {
    Names items;
    for (const std::string& key : keys_in_written_order(*t))
      items.push_back(fmt::format("{} = {}", key_text(key), inline_toml(*t->get(key))));
    return items.empty() ? "{}" : fmt::format("{{ {} }}", fmt::join(items, ", "));
  }
  std::ostringstream other;  // dates and times: never valid in a spec, but shown in messages
  node.visit([&](const auto& value) {
    if constexpr (requires { other << value.get(); }) other << value.get();
  });
  return other.str();
}

std::string shown(const toml::node& node) {
  constexpr std::size_t kMaxShown = 80;
  std::string text = inline_toml(node);
  return text.size() <= kMaxShown ? text : text.substr(0, kMaxShown - 3) + "...";
}

std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    default:
      return "a date/time";
  }
}

std::string canonical_text(const toml::table& doc, const Names& grid_order) {
  std::string text;
  if (const toml::node* title = doc.get("title")) text += "title = " + inline_toml(*title) + "\n";
  for (const std::string_view name : kSections) {
    const toml::table* section = doc[name].as_table();
    if (section == nullptr) continue;
    text += fmt::format("{}[{}]\n", text.empty() ? "" : "\n", name);
    const Names keys = name == "grid" ? grid_order : keys_in_written_order(*section);
    for (const std::string& key : keys)
      text += fmt::format("{} = {}\n", key_text(key), inline_toml(*section->get(key)));
  }
  return text;
}

}  // namespace cs::spec
