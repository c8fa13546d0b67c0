// The subcommands of the `contactsweep` executable. Each returns the process exit status:
// 0 success, 1 run-time failure (I/O, MPI), 2 bad input (INTERFACE.md).
#pragma once

#include <mpi.h>

#include "parallel/run_entry.hpp"  // RunArguments

namespace cs {

int run_command(const RunArguments& args, MPI_Comm comm);
void print_scenes();
void print_methods();

}  // namespace cs
