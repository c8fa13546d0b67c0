// Which compiler builds the kernels, as the kernel key must name it.
#pragma once

#include <string>

namespace cs {

// The compiler's identity as it reports it (`--version`): an upgraded compiler under the same
// path builds another key. Starting a compiler costs milliseconds, so the answer is kept in the
// cache under the signature of the compiler's file and asked again only when that changes.
std::string compiler_identity(const std::string& compiler);

}  // namespace cs
