// contactsweep: parallel ensemble and parameter-sweep runner for contact Hamiltonian dynamics.
// MPI starts only for a run that an MPI launcher started (mpirun, srun): --version, --help,
// `scenes`, `methods` and a run in one process never pay for it. Only rank 0 prints.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "cli/commands.hpp"
#include "io/log.hpp"
#include "io/output_file.hpp"
#include "model/run_spec.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "parallel/stop_signal.hpp"
#include "parallel/sweep.hpp"
#include "version.hpp"

namespace {

std::string joined(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) s += (i ? " " : "") + std::string(argv[i]);
  return s;
}

// The rank a launcher gave this process (mpirun, srun), read from its environment: commands
// that need no MPI run without MPI_Init and must still print once.
int launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 0;
}

// What the command line asks for: a run, or an exit status once everything else is done.
struct Parsed {
  cs::RunArguments run;
  bool is_run = false;
  int status = 0;
};

// Everything but `run` is done here, before MPI exists: --version, --help, `scenes`, `methods`
// and command-line errors never pay for MPI's start-up (~0.4 s for a singleton; ~5 ms without).
Parsed parse_command_line(int argc, char** argv, int rank) {
  CLI::App app{"contactsweep: ensembles and parameter sweeps of contact Hamiltonian dynamics"};
  app.set_version_flag("--version", std::string("contactsweep ") + cs::kVersion);
  app.require_subcommand(1);

  Parsed parsed;
  cs::RunArguments& run = parsed.run;
  run.command_line = joined(argc, argv);
  auto* run_cmd = app.add_subcommand("run", "integrate the grid of a spec file into an HDF5 file");
  run_cmd->add_option("spec", run.spec_path, "spec file (TOML)")->required();
  auto* output = run_cmd->add_option(
      "-o,--output", run.output,
      "output file (default: the spec's name with .h5, in the current directory)");
  run_cmd->add_option("--set", run.overrides,
                      "override one spec value by its dotted key, e.g. integrator.h=0.005")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  auto* resume = run_cmd->add_flag("--resume", run.resume,
                                   "continue this very run from what it had finished");
  auto* force = run_cmd->add_flag("--force", run.force, "replace an existing output");
  resume->excludes(force);
  run_cmd->add_flag("--quiet", run.quiet, "no progress reports");
  auto* scenes = app.add_subcommand("scenes", "list scenes, their parameters and state variables");
  auto* methods = app.add_subcommand("methods", "list integrators, their order and properties");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = rank == 0 ? app.exit(e) : e.get_exit_code();  // prints help, version, error
    parsed.status = code == 0 ? 0 : 2;
    return parsed;
  }
  run.output_given = output->count() > 0;
  if (scenes->parsed() && rank == 0) cs::print_scenes();
  if (methods->parsed() && rank == 0) cs::print_methods();
  // A listing asked for and not delivered (stdout on a full disk) is a failure.
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) parsed.status = 1;
  parsed.is_run = run_cmd->parsed();
  return parsed;
}

// Whether an MPI launcher started this process: mpirun (Open MPI, MPICH's Hydra) and srun
// leave these in every rank's environment. Without one the run is this process alone, and MPI
// is never initialised: its singleton start-up (~0.4 s) would cost more than a small run.
bool started_by_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

int run(int argc, char** argv, const cs::RunArguments& arguments) {
  MPI_Comm comm = MPI_COMM_NULL;  // one process without MPI (mpi/comm.hpp)
  if (started_by_launcher()) {
    // Funneled: OpenMP threads compute while the main thread alone talks MPI (sweep.cpp polls
    // whether another rank failed between blocks).
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    comm = MPI_COMM_WORLD;
  }
  // After MPI_Init, so that the handler is ours whatever the MPI library installs.
  cs::install_stop_signal_handler();
  const int rank = cs::rank_of(comm), size = cs::size_of(comm);
  int status = 0;
  try {
    status = cs::run_command(arguments, comm);
  } catch (const cs::StoppedBySignal& e) {  // every rank together (parallel/stop_signal.hpp)
    if (rank == 0) cs::log("contactsweep: {}", e.what());
    // 128 + the signal, as a shell reports a process that signal ended.
    status = 128 + e.signal;
  } catch (const cs::InputError& e) {  // every rank throws it together (mpi/agreement.hpp)
    if (rank == 0) cs::log("contactsweep: error: {}", e.what());
    status = 2;
  } catch (const cs::CollectiveError& e) {
    if (rank == 0) cs::log("contactsweep: run-time failure: {}", e.what());
    status = 1;
  } catch (const std::exception& e) {  // this rank alone: the others may wait for it forever
    cs::log("contactsweep: run-time failure on rank {}: {}", rank, e.what());
    if (size > 1) MPI_Abort(comm, 1);
    status = 1;
  }
  // Rank 0 writes the file alone; every rank agreed on the failure that left it open
  // (io/output_file.hpp), the journal holds the results and the partial file is gone.
  // Finalizing would crash inside HDF5, so all ranks end together without it.
  int left_open = cs::hdf5_files_left_open() ? 1 : 0;
  cs::allreduce(comm, &left_open, 1, MPI_INT, MPI_MAX);
  if (left_open) std::_Exit(status);
  if (!cs::serial(comm)) MPI_Finalize();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  // A closed stderr pipe must not kill a run that is writing its map (io/log.hpp).
  std::signal(SIGPIPE, SIG_IGN);
  try {
    const Parsed parsed = parse_command_line(argc, argv, launcher_rank());
    if (!parsed.is_run) return parsed.status;
    return run(argc, argv, parsed.run);
  } catch (const std::exception& e) {  // listing scenes or methods to a stdout that fails
    cs::log("contactsweep: failure: {}", e.what());
    return 1;
  }
}
