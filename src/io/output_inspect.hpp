// Reading back what an earlier run left: the spec a finished output was made from, so that
// `--resume` can tell "this very run, already complete" from "another run's file".
#pragma once

#include <optional>
#include <string>

namespace cs {

// The root attribute `spec` of an HDF5 file; nullopt when the file cannot be read as a
// contactsweep output. Serial HDF5, any rank.
std::optional<std::string> read_spec_attribute(const std::string& path);

}  // namespace cs
