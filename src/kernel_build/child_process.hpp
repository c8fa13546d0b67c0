// Starting the compiler (kernel_cache.cpp, compiler_identity.cpp) as a child that cannot outlive
// this process.
#pragma once

#include <string>
#include <vector>

namespace cs {

// Runs `args` with stdout and stderr on `output_fd`; returns its exit status. The child dies
// with this process (a killed run leaves no compiler behind) and sees `extra_env` on top of
// ours. Throws when the program cannot be started, saying why (not found, not executable, ...).
int run_program(const std::vector<std::string>& args, int output_fd,
                const std::vector<std::string>& extra_env = {});

}  // namespace cs
