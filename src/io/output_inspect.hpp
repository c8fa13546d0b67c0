// Reading back what an earlier run left: the spec a finished output was made from, so that
// `--resume` can tell "this very run, already complete" from "another run's file".
#pragma once

#include <optional>
#include <string>

namespace cs {

// An existing output as this user's finished work. Only a regular file the user owns counts,
// opened without following a link and read through that descriptor: a file another user put
// under the output's name (in a shared directory), or a link, says nothing of what this user
// ran, whatever its `spec` attribute says (a spec's text is no secret), so it is never taken as
// a finished run, which would report its numbers and remove the journal of the real one.
struct ExistingOutput {
  bool ours = false;
  std::string why_not;              // when not ours: "is a symbolic link", "belongs to user id N", ...
  std::optional<std::string> spec;  // when ours: its `spec` attribute, if it has one
};
ExistingOutput inspect_existing_output(const std::string& path);

}  // namespace cs
