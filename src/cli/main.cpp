// contactsweep: parallel ensemble and parameter-sweep runner for contact Hamiltonian dynamics.
// Every rank parses the same command line and spec; only rank 0 prints.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <exception>
#include <string>

#include "cli/commands.hpp"
#include "io/run_spec.hpp"
#include "version.hpp"

namespace {

std::string joined(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) s += (i ? " " : "") + std::string(argv[i]);
  return s;
}

int main_with_mpi(int argc, char** argv, int rank) {
  CLI::App app{"contactsweep: ensembles and parameter sweeps of contact Hamiltonian dynamics"};
  app.set_version_flag("--version", std::string("contactsweep ") + cs::kVersion);
  app.require_subcommand(1);

  cs::RunArguments run;
  run.command_line = joined(argc, argv);
  auto* run_cmd = app.add_subcommand("run", "integrate the grid of a spec file into an HDF5 file");
  run_cmd->add_option("spec", run.spec_path, "spec file (TOML)")->required();
  run_cmd->add_option("-o,--output", run.output,
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
    if (rank != 0) return e.get_exit_code() == 0 ? 0 : 2;
    int code = app.exit(e);  // prints help, version or the error
    return code == 0 ? 0 : 2;
  }
  if (scenes->parsed()) {
    if (rank == 0) cs::print_scenes();
    return 0;
  }
  if (methods->parsed()) {
    if (rank == 0) cs::print_methods();
    return 0;
  }
  return cs::run_command(run, MPI_COMM_WORLD);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int status = 0;
  try {
    status = main_with_mpi(argc, argv, rank);
  } catch (const cs::InputError& e) {
    if (rank == 0) fmt::print(stderr, "contactsweep: error: {}\n", e.what());
    status = 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "contactsweep: run-time failure on rank {}: {}\n", rank, e.what());
    if (size > 1) MPI_Abort(MPI_COMM_WORLD, 1);
    status = 1;
  }
  MPI_Finalize();
  return status;
}
