// The one entry of a run, for the command line (cli/commands.cpp) and the Python module
// (python/module.cpp): the spec read and agreed on, the output named, the sweep run. Each caller
// only reports the outcome its own way.
#pragma once

#include <mpi.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "parallel/sweep.hpp"

namespace cs {

struct RunArguments {
  std::string spec_path;  // read by rank 0, unless spec_text is given; names the spec in messages
  std::optional<std::string> spec_text;  // the spec itself (the module's TOML text or dict)
  std::string output;         // empty: the spec's name with .h5, in the current directory
  bool output_given = false;  // -o was passed (an empty -o '' is an error, not the default)
  std::vector<std::string> overrides;
  bool resume = false;
  bool force = false;
  bool quiet = false;
  std::string command_line;
  // One process only (MPI_COMM_NULL). When set, the run computes on a thread of its own with
  // `threads` OpenMP threads (0: OpenMP's default) and the calling thread calls `tick` with the
  // share done about every 0.1 s; `tick` returning false stops the run (Interrupted).
  std::function<bool(double fraction)> tick;
  int threads = 0;
};

struct RunOutcome {
  std::string output;      // the file written (or found complete)
  std::int64_t steps = 0;  // per trajectory, for the rate the CLI reports
  bool adaptive = false;   // an adaptive method: its lane-steps are attempts, not t_end / h each
  SweepSummary summary;
};

// Collective over `comm`; throws what run_sweep throws (InputError, CollectiveError,
// Interrupted) on every rank together.
RunOutcome run(const RunArguments& args, MPI_Comm comm);

}  // namespace cs
