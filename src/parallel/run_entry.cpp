#include "parallel/run_entry.hpp"

#include <omp.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "io/spec_parser.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "numerics/method_catalog.hpp"
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

// `--set a=1 --set b=2` as it was typed, for a message.
std::string as_typed(const std::vector<std::string>& overrides) {
  if (overrides.empty()) return "no --set";
  std::string s;
  for (const auto& o : overrides) s += (s.empty() ? "" : " ") + ("--set " + o);
  return s;
}

// Collective: rank 0's list on every rank.
std::vector<std::string> rank0_list(MPI_Comm comm, const std::vector<std::string>& mine) {
  std::vector<std::string> list = mine;
  std::string count = std::to_string(list.size());
  broadcast(comm, count);
  list.resize(std::stoull(count));
  for (auto& item : list) broadcast(comm, item);
  return list;
}

// Collective, before anything else of the run: every rank was started with the same --set
// overrides and writes the same output. One `mpirun -np N contactsweep …` gives every rank the
// same command line, but an MPMD launch (`mpirun -np 1 contactsweep run … : -np 1 contactsweep
// run …`) or a wrapper script per rank may not, and each rank uses its own: it parses rank 0's
// spec text with its own overrides (so its grid and blocks may differ, and the ranks would part
// ways in their collective calls before any check of the run's identity), and it saves its
// blocks in the journal beside its own output while rank 0 decides the start and writes the
// file for its own. Either is bad input (exit 2), named, before any work.
void check_same_arguments(const RunArguments& args, const std::string& output, MPI_Comm comm) {
  const std::vector<std::string> rank0_overrides = rank0_list(comm, args.overrides);
  // Compared as absolute paths: `out.h5` and `./out.h5` are one file; the same relative name in
  // two working directories is two.
  std::error_code no_directory;  // the working directory gone: compared as given
  std::string absolute =
      std::filesystem::absolute(output, no_directory).lexically_normal().string();
  if (no_directory) absolute = output;
  const std::vector<std::string> rank0_output = rank0_list(comm, {output, absolute});
  agreed(comm, [&] {
    if (args.output_given && args.output.empty())
      throw InputError("-o: the output path is empty; name a file, e.g. -o basins.h5");
    if (args.overrides != rank0_overrides)
      throw InputError("this rank was started with other overrides than rank 0 (" +
                       as_typed(args.overrides) + " here, " + as_typed(rank0_overrides) +
                       " on rank 0); every rank of a run must be given the same --set");
    if (absolute != rank0_output[1]) {
      // The same name in two working directories: the directories are the difference.
      const bool same_name = output == rank0_output[0];
      throw InputError("this rank would write '" + (same_name ? absolute : output) +
                       "' but rank 0 writes '" + rank0_output[same_name ? 1 : 0] +
                       "' (-o, or the spec's name with .h5 without -o); every rank of a run must "
                       "be given the same -o");
    }
  });
}

RunOutcome run_here(const RunArguments& args, MPI_Comm comm, RunControl* control) {
  const std::string output = args.output.empty()
                                 ? std::filesystem::path(args.spec_path).stem().string() + ".h5"
                                 : args.output;
  check_same_arguments(args, output, comm);
  RunOutcome outcome;
  const RunSpec spec = agreed_spec(args, comm);
  SweepOptions options;
  options.output = output;
  options.force = args.force;
  options.resume = args.resume;
  options.quiet = args.quiet;
  options.command_line = args.command_line;
  options.control = control;
  outcome.output = options.output;
  outcome.steps = spec.steps;
  const MethodInfo* method = find_method(spec.method);
  outcome.adaptive = method != nullptr && method->adaptive;
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
