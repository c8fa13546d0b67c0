// --set overrides ("dotted.key=VALUE", VALUE a TOML value) merged into the parsed document.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <vector>

#include "io/spec_names.hpp"

namespace cs::spec {

// Applies `overrides` to `doc` in order and returns the grid axes in grid order: the file's
// order, an axis changed by --set in its place, a new axis last. The nodes an override brings
// carry its argument as their source ("--set ARG"), for messages. Throws InputError.
Names apply_overrides(toml::table& doc, const std::vector<std::string>& overrides);

}  // namespace cs::spec
