// The subcommands of the `contactsweep` executable. Each returns the process exit status:
// 0 success, 1 run-time failure (I/O, MPI), 2 bad input (INTERFACE.md).
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

namespace cs {

struct RunArguments {
  std::string spec_path;
  std::string output;  // empty: the spec's name with .h5, in the current directory
  bool output_given = false;  // -o was passed (an empty -o '' is an error, not the default)
  std::vector<std::string> overrides;
  bool resume = false;
  bool force = false;
  bool quiet = false;
  std::string command_line;
};

int run_command(const RunArguments& args, MPI_Comm comm);
void print_scenes();
void print_methods();

}  // namespace cs
