#include "cli/commands.hpp"

#include <fmt/core.h>
#include <fmt/format.h>

#include <filesystem>

#include "io/spec_parser.hpp"
#include "numerics/method_catalog.hpp"
#include "parallel/sweep.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

int run_command(const RunArguments& args, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  RunSpec spec = load_run_spec(args.spec_path, args.overrides);
  SweepOptions options;
  options.output = args.output.empty()
                       ? std::filesystem::path(args.spec_path).stem().string() + ".h5"
                       : args.output;
  options.force = args.force;
  options.resume = args.resume;
  options.quiet = args.quiet;
  options.command_line = args.command_line;
  SweepSummary s = run_sweep(spec, options, comm);
  if (s.already_complete) {
    if (rank == 0 && !args.quiet)
      fmt::print(stderr, "contactsweep: {} is already complete for this spec; nothing to do\n",
                 options.output);
    return 0;
  }
  if (rank == 0 && !args.quiet) {
    double rate = static_cast<double>(s.points) * static_cast<double>(spec.steps) / s.seconds;
    fmt::print(stderr,
               "contactsweep: wrote {} ({} points x {} steps in {:.3f} s, {:.3g} traj-steps/s); "
               "flagged: {} diverged, {} integrator breakdown\n",
               options.output, s.points, spec.steps, s.seconds, rate, s.flagged_diverged,
               s.flagged_breakdown);
  }
  return 0;
}

void print_scenes() {
  for (const auto& s : scene_catalog()) {
    fmt::print("{} (paper scene {})\n  {}\n  degrees of freedom: {}; z feeds back: {}\n", s.name,
               s.paper_label, s.hamiltonian, s.dof, s.z_feeds_back ? "yes" : "no");
    fmt::print("  parameters (paper values as defaults):\n");
    for (const auto& p : s.parameters)
      fmt::print("    {:<10} = {:<6g} {}\n", p.name, p.paper_value, p.description);
    fmt::print("  state variables (paper initial values as defaults):\n");
    for (const auto& v : s.variables)
      fmt::print("    {:<10} = {:<6g} {}\n", v.name, v.paper_value, v.description);
    fmt::print("  measures: {}\n  exact sub-flows for splitting: {}\n  defaults: h = {}, t_end = {}\n\n",
               fmt::join(s.measures, ", "), fmt::join(s.split_parts, ", "), s.default_h,
               s.default_t_end);
  }
}

void print_methods() {
  for (const auto& m : method_catalog()) {
    fmt::print("{}\n  order {}, {} force evaluation(s) per step\n  {}\n", m.name, m.order,
               m.force_evaluations_per_step, m.properties);
    if (!m.needs_split_parts.empty())
      fmt::print("  needs scene sub-flows: {}\n", fmt::join(m.needs_split_parts, ", "));
    fmt::print("\n");
  }
}

}  // namespace cs
