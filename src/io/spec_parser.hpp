// Reading a spec file (INTERFACE.md, "Spec files") into a validated RunSpec.
//
// All checking of user input happens here, so every message can name the file position (or the
// --set argument), the key, the offending value and what was expected. Decisions beyond
// INTERFACE.md, kept here so users and the engine can rely on them:
// - A grid axis wins over the same parameter in [scene] (or the same variable in [initial]):
//   the [scene]/[initial] value stays in RunSpec::parameters/initial as the base value and the
//   axis replaces it point by point. Refusing would break `--set grid.gamma=...` on a spec that
//   sets scene.gamma, since --set can add keys but not remove them.
// - t_end must be a whole number of steps: steps = llround(t_end / h), accepted when
//   |steps * h - t_end| <= 1e-9 * t_end; RunSpec::t_end keeps the value as written.
// - No [measures] section means final_state = true. A [measures] section that requests nothing
//   is an error (most likely every measure was switched off by mistake).
// - final_state vars are stored in the scene's variable order, whatever order the spec lists.
// - sync = true or sync = {} measures over the second half of the run, [t_end / 2, t_end].
// - The initial lambda (and a lambda_0 axis) must be > 0: lambda is an integrating factor and
//   the kernel carries ln(lambda).
// - Limits, refused with a message: at most 2^40 grid points, 2^32 points per axis, 2^53 steps.
// - spec_text is the document after --set in a fixed layout that reads back to the same RunSpec:
//   title, then [scene] [initial] [integrator] [grid] [measures], every value inline, the keys
//   name, method, h, t_end, from, to, n first, grid axes in grid order, floats in their shortest
//   exact form; comments are dropped.
// - A --set VALUE that is not valid TOML but is a bare word (letters, digits, _ and -) is taken
//   as a string, because the shell eats the quotes of --set scene.name="double_well".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/linspace.hpp"  // for callers of linspace, which the spec files use
#include "model/run_spec.hpp"

namespace cs {

// Parses and validates a spec, after applying --set overrides ("dotted.key=VALUE", VALUE a TOML
// value). `source_name` (usually the file name) prefixes messages. Throws InputError.
RunSpec parse_run_spec(std::string_view toml_text, const std::vector<std::string>& overrides,
                       std::string_view source_name);

// The text of the spec file at `path`; an unreadable file is an InputError naming the path.
std::string read_spec_file(const std::string& path);

// Reads the file at `path` and parses it; an unreadable file is an InputError naming the path.
RunSpec load_run_spec(const std::string& path, const std::vector<std::string>& overrides);

}  // namespace cs
