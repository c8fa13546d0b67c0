// The parallel driver: cuts the grid into blocks of points, deals them to MPI ranks
// round-robin and to OpenMP threads dynamically, journals each finished block, and has rank 0
// write every rank's blocks into one HDF5 file. Blocks hold whole lanes, and a lane's result
// depends on nothing but its own point, so the file has the same bits for any number of ranks
// and threads. `comm` may be MPI_COMM_NULL: one process without MPI (mpi/comm.hpp).
#pragma once

#include <mpi.h>

#include <stdexcept>
#include <string>

#include "model/run_spec.hpp"

namespace cs {

class RunControl;  // parallel/progress.hpp

struct SweepOptions {
  std::string output;   // final path of the HDF5 file
  bool force = false;   // replace an existing output
  bool resume = false;  // continue this very run if its output exists
  bool quiet = false;   // no progress reports
  std::string command_line;  // for the `history` attribute
  RunControl* control = nullptr;  // watched from another thread: progress, stop (one process)
};

// The run was stopped through its RunControl: no block started after the request, no output
// written, the journal removed (sweep.cpp).
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The run was stopped by a signal (SIGTERM, SIGINT: parallel/stop_signal.hpp), thrown on every
// rank together: no block was started after it, every block finished is saved in the journal,
// which stays for --resume, and the temporary output is removed. what() says so (rank 0 prints
// it); the program exits with 128 + `signal`.
class StoppedBySignal : public std::runtime_error {
 public:
  StoppedBySignal(int signal, const std::string& message)
      : std::runtime_error(message), signal(signal) {}
  int signal;
};

struct SweepSummary {
  std::int64_t points = 0;
  std::int64_t computed_points = 0;  // integrated by this invocation (not loaded on --resume)
  std::int64_t flagged_diverged = 0;
  std::int64_t flagged_breakdown = 0;
  std::int64_t flagged_non_finite = 0;          // status 3: a value written is not finite
  std::int64_t flagged_undefined_at_start = 0;  // status 4: K undefined at the initial state
  std::int64_t lane_steps = 0;  // steps integrated by this invocation: less than computed_points
                                // × steps where lanes stopped early (a basin decided, a failure)
  double seconds = 0.0;
  bool already_complete = false;
};

// Collective over `comm`. Every failure is thrown on every rank together (agreement.hpp):
// InputError for input the user must change (an output that must not be overwritten, a run
// that does not fit), CollectiveError for run-time failures (I/O).
SweepSummary run_sweep(const RunSpec& spec, const SweepOptions& options, MPI_Comm comm);

}  // namespace cs
