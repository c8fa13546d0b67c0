// "Did you mean": the name a user most likely meant, for messages about unknown keys and names.
#pragma once

#include <string>
#include <string_view>

#include "io/spec_names.hpp"

namespace cs::spec {

// " (did you mean 'prefix.candidate'?)" for the candidate closest to `key` (an alias such as
// dt for h, q for q_0, or about one typo per three characters), or "" if none is close enough.
std::string did_you_mean(std::string_view key, const Names& candidates, std::string_view prefix);

// The literature (Bravetti et al., de León et al.) names the contact variable s; contactsweep
// names it z, with z = −s. For `s`, `s_0`, `final_s`, `s_end` ... where a z name exists among
// `candidates`: " (contactsweep calls it z (z = −s): did you mean 'prefix.z_name'? ...)", else "".
std::string contact_variable_hint(std::string_view key, const Names& candidates,
                                  std::string_view prefix);

}  // namespace cs::spec
