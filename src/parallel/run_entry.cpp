#include "parallel/run_entry.hpp"

#include <omp.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "io/spec_parser.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "parallel/progress.hpp"

namespace cs {
namespace {

// Rank 0 alone reads the spec (a path such as /dev/stdin, or a file on a node-local disk, may
// be readable there only) and every rank parses the same text; the parse also checks the grid
// against each node's memory, so its outcome is agreed.
RunSpec agreed_spec(const RunArguments& args, MPI_Comm comm) {
  const int rank = rank_of(comm);
  std::string text = agreed(comm, [&] {
    if (args.spec_text) return *args.spec_text;
    return rank == 0 ? read_spec_file(args.spec_path) : std::string();
  });
  broadcast(comm, text);
  return agreed(comm, [&] { return parse_run_spec(text, args.overrides, args.spec_path); });
}

RunOutcome run_here(const RunArguments& args, MPI_Comm comm, RunControl* control) {
  if (args.output_given && args.output.empty())
    throw InputError("-o: the output path is empty; name a file, e.g. -o basins.h5");
  RunOutcome outcome;
  const RunSpec spec = agreed_spec(args, comm);
  SweepOptions options;
  options.output = args.output.empty()
                       ? std::filesystem::path(args.spec_path).stem().string() + ".h5"
                       : args.output;
  options.force = args.force;
  options.resume = args.resume;
  options.quiet = args.quiet;
  options.command_line = args.command_line;
  options.control = control;
  outcome.output = options.output;
  outcome.steps = spec.steps;
  outcome.summary = run_sweep(spec, options, comm);
  return outcome;
}

// The run on a thread of its own, so that the caller's thread stays free for `tick` (the Python
// module holds the interpreter there: its bar and Ctrl-C). The OpenMP team is the worker's: its
// thread count is set there and the file's omp_threads attribute reads it there.
RunOutcome run_watched(const RunArguments& args) {
  RunControl control;
  RunOutcome outcome;
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  std::thread worker([&] {
    try {
      if (args.threads > 0) omp_set_num_threads(args.threads);
      outcome = run_here(args, MPI_COMM_NULL, &control);
    } catch (...) {
      failure = std::current_exception();
    }
    const std::lock_guard lock(mutex);
    done = true;
    done_cv.notify_all();
  });
  for (;;) {
    {
      std::unique_lock lock(mutex);
      if (done_cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return done; })) break;
    }
    bool go_on = false;
    try {
      go_on = args.tick(control.fraction());
    } catch (...) {  // the caller's own failure: stop the run, then hand it back
      control.request_stop();
      worker.join();
      throw;
    }
    if (!go_on) control.request_stop();
  }
  worker.join();
  if (failure) std::rethrow_exception(failure);
  args.tick(1.0);
  return outcome;
}

}  // namespace

RunOutcome run(const RunArguments& args, MPI_Comm comm) {
  if (!args.tick) return run_here(args, comm, nullptr);
  if (!serial(comm)) throw std::logic_error("a watched run is one process (MPI_COMM_NULL)");
  return run_watched(args);
}

}  // namespace cs
