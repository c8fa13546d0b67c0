#include "cli/commands.hpp"

#include <fmt/core.h>
#include <fmt/format.h>

#include "io/log.hpp"
#include "mpi/comm.hpp"
#include "numerics/method_catalog.hpp"
#include "parallel/run_entry.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

int run_command(const RunArguments& args, MPI_Comm comm) {
  const int rank = rank_of(comm);
  const RunOutcome outcome = run(args, comm);
  const SweepSummary& s = outcome.summary;
  const std::int64_t steps = outcome.steps;
  if (rank != 0 || args.quiet) return 0;
  if (s.already_complete) {
    log("contactsweep: {} is already complete for this spec; nothing to do", outcome.output);
    return 0;
  }
  // The rate counts the points integrated by this invocation, not blocks a resume loaded.
  // Scripts parse "steps in X s" (jobs/bench_basins.sh, work_precision.py): keep that shape.
  const double rate = static_cast<double>(s.computed_points) * static_cast<double>(steps) /
                      s.seconds;
  const std::string resumed =
      s.computed_points < s.points
          ? fmt::format("; {} points loaded from the journal, {} integrated",
                        s.points - s.computed_points, s.computed_points)
          : "";
  // When lanes stop early the nominal rate overstates the work: say what was integrated. An
  // adaptive method's steps are its attempts, which may outnumber the nominal t_end / h or fall
  // short of it with no lane stopped early: its share is of the nominal count, whichever.
  const double nominal = static_cast<double>(s.computed_points) * static_cast<double>(steps);
  const auto done = static_cast<double>(s.lane_steps);
  std::string integrated;
  if (done < nominal && !outcome.adaptive)
    integrated = fmt::format("; {:.3g} lane-steps integrated ({:.0f} %, the rest stopped early), "
                             "{:.3g}/s",
                             done, 100.0 * done / nominal, done / s.seconds);
  else if (done != nominal)
    integrated = fmt::format("; {:.3g} lane-steps integrated ({:.0f} % of the nominal t_end / h: "
                             "an adaptive method's attempts), {:.3g}/s",
                             done, 100.0 * done / nominal, done / s.seconds);
  log("contactsweep: wrote {} ({} points x {} steps in {:.3f} s, {:.3g} traj-steps/s{}{}); "
      "flagged: {} diverged, {} integrator breakdown, {} non-finite output, {} K undefined at "
      "the initial state",
      outcome.output, s.points, steps, s.seconds, rate, integrated, resumed,
      s.flagged_diverged, s.flagged_breakdown, s.flagged_non_finite, s.flagged_undefined_at_start);
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
    fmt::print("  step size: {}\n", m.adaptive ? "adaptive per lane (integrator.rtol, atol)"
                                                : "fixed (integrator.h)");
    if (!m.needs_split_parts.empty())
      fmt::print("  needs scene sub-flows: {}\n", fmt::join(m.needs_split_parts, ", "));
    fmt::print("\n");
  }
}

}  // namespace cs
