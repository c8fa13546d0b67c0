// Starting the compiler (kernel_cache.cpp, compiler_identity.cpp) as a child that cannot outlive
// this process.
#pragma once

#include <string>
#include <vector>

namespace cs {

// Runs `args` with stdout and stderr on `output_fd`; returns its exit status. The child dies
// with this process (a killed run leaves no compiler behind) and sees `extra_env` on top of
// our environment less GCC's search variables (child_process.cpp, compiler_environment). With `directory_fd` >= 0 it runs in that directory, entered by its
// descriptor: names relative to it then reach the directory this process checked and opened,
// whatever becomes of the path to it (another user who can rename a parent cannot swap it).
// Throws when the program cannot be started, saying why (not found, not executable, ...).
int run_program(const std::vector<std::string>& args, int output_fd,
                const std::vector<std::string>& extra_env = {}, int directory_fd = -1);

}  // namespace cs
