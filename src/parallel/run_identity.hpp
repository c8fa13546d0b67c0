// What makes two invocations the same run, so that a journal's blocks are only ever combined with
// blocks of the very computation that made them. The version string alone did not do it: it
// stayed "0.1.0" across dozens of commits that changed results.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace cs {

// FNV-1a, 64 bits: identities are compared, not defended against an adversary.
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = 1469598103934665603ull);

// The build that computes: the GNU build-id the linker writes into the executable (a hash of
// its contents), read from memory at no cost; a hash of /proc/self/exe's bytes where there is
// none. Any change of source, compiler or flags gives another identity.
const std::string& build_identity();

// Hex digest of everything a result depends on: the canonical spec text (after --set), the
// build, and the cut of the grid into blocks (the journal's unit).
std::string run_identity(const std::string& spec_text, std::int64_t points,
                         std::int64_t block_size);

}  // namespace cs
