// TOML as text: the canonical spec_text stored in the output (the document after --set,
// sections in a fixed order, grid axes in grid order, every value inline, comments dropped), and
// values as messages show them.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <string_view>

#include "io/spec_names.hpp"

namespace cs::spec {

// The document in a fixed layout that reads back to the same RunSpec: title, then [scene]
// [initial] [integrator] [grid] [measures], the keys name, method, h, t_end, from, to, n first,
// grid axes in `grid_order`, floats in their shortest exact form.
std::string canonical_text(const toml::table& doc, const Names& grid_order);

// A value in TOML's one-line syntax.
std::string inline_toml(const toml::node& node);
// inline_toml, cut to 80 characters for a message.
std::string shown(const toml::node& node);
// "a string", "an integer", ...: what a message says a value is.
std::string_view type_name(const toml::node& node);
// A TOML basic string, quoted and escaped.
std::string toml_string(std::string_view text);
// Letters, digits, _ and -: a key TOML takes without quotes.
bool is_bare_key(std::string_view key);

}  // namespace cs::spec
