#include "parallel/sweep.hpp"

#include <fmt/core.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "engine/attractor_analysis.hpp"
#include "engine/basin_column.hpp"
#include "engine/fixed_point_exponent.hpp"
#include "engine/mappers/energy_trap_record.hpp"
#include "engine/mappers/mapper_choice.hpp"
#include "engine/run_plan.hpp"
#include "engine/step_kernel_runner.hpp"
#include "formula/custom_scene.hpp"
#include "io/log.hpp"
#include "io/memory_budget.hpp"
#include "kernel_build/kernel_cache.hpp"
#include "kernel_build/kernel_source.hpp"
#include "kernel_build/sha256.hpp"
#include "formula/measure_formulas.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "mpi/failure_watch.hpp"
#include "parallel/basin_summary.hpp"
#include "parallel/block_stream.hpp"
#include "parallel/journal.hpp"
#include "parallel/journal_writer.hpp"
#include "parallel/output_assembly.hpp"
#include "parallel/progress.hpp"
#include "parallel/run_identity.hpp"
#include "parallel/run_start.hpp"
#include "parallel/stop_signal.hpp"

namespace cs {
namespace {

struct Comm {
  MPI_Comm comm;
  int rank = 0, size = 1;
  explicit Comm(MPI_Comm c) : comm(c), rank(rank_of(c)), size(size_of(c)) {}
};

// Blocks are the unit of load balance and of the journal. Their size is a function of the spec
// alone, never of a rank's threads or the rank count: ranks with different resources (a Slurm
// job over nodes with different CPU masks) must deal the same block list, and a journal must be
// resumable on any layout. A block holds about 5e7 lane-steps (0.1-0.3 s on one core), so the
// fsync of its journal file costs under 1%; but the grid is cut into at least 64 blocks so that
// small runs still spread over the threads of several ranks.
std::int64_t choose_block_size(std::int64_t points, std::int64_t steps) {
  constexpr double kLaneStepsPerBlock = 5e7;
  constexpr std::int64_t kMinBlocks = 64, kMinPoints = 256, kMaxPoints = std::int64_t{1} << 20;
  const auto by_work = static_cast<std::int64_t>(
      std::ceil(kLaneStepsPerBlock / static_cast<double>(std::max<std::int64_t>(steps, 1))));
  const std::int64_t by_count = (points + kMinBlocks - 1) / kMinBlocks;
  return std::clamp(std::min(by_work, by_count), kMinPoints, kMaxPoints);
}

struct Block {
  PointRange range;
  const RunPlan* plan;  // the slice (step size) it belongs to
};

// Blocks never straddle two slices; they are dealt round-robin over the whole list. Interleaving
// spreads the spatially correlated cost of early-stopping lanes: on the 512² basin map (cost of a
// cell = its settle time) the busiest rank has 1.000, 1.002, 1.003 and 1.005 times the mean work
// at 2, 4, 8 and 64 ranks, so ranks need no dynamic stealing (threads within a rank have it).
std::vector<Block> my_blocks(const std::vector<std::unique_ptr<RunPlan>>& slices,
                             std::int64_t block, const Comm& c) {
  std::vector<Block> blocks;
  std::int64_t index = 0;
  for (const auto& plan : slices) {
    const std::int64_t begin = plan->point_offset, end = begin + plan->grid.size();
    for (std::int64_t b = begin; b < end; b += block, ++index)
      if (index % c.size == c.rank) blocks.push_back({{b, std::min(end, b + block)}, plan.get()});
  }
  return blocks;
}

// How many of a block's lanes ended with each failing status (the summary line): counted as
// the block finishes, since its `status` column is freed once written (block_stream.hpp).
using StatusCounts = std::array<std::atomic<std::int64_t>, 4>;
constexpr LaneStatus kCountedStatuses[4] = {LaneStatus::diverged, LaneStatus::breakdown,
                                            LaneStatus::non_finite,
                                            LaneStatus::undefined_at_start};

void count_statuses(const BlockResults& block, int column, StatusCounts& counts) {
  std::int64_t n[4] = {};
  for (double v : block.columns[static_cast<std::size_t>(column)])
    for (int s = 0; s < 4; ++s) n[s] += v == static_cast<double>(kCountedStatuses[s]);
  for (int s = 0; s < 4; ++s) counts[static_cast<std::size_t>(s)] += n[s];
}

double values_per_point(const RunPlan& plan) {
  double values = 0.0;
  for (const auto& column : plan.columns)
    if (!column.per_block) values += static_cast<double>(column.width);
  return values;
}

double file_bytes(const RunPlan& plan) {
  return static_cast<double>(plan.grid.size()) * values_per_point(plan) * sizeof(double);
}

// What a rank holds, in doubles: the columns written as blocks finish only while the blocks are
// in flight; `basin` (compact) and the basin summary's internal columns for each of its blocks
// until the end (a per-block column counted once per block).
struct HeldValues {
  double per_point_in_flight = 0.0, per_point_kept = 0.0, per_block_kept = 0.0;
};

HeldValues held_values(const RunPlan& plan) {
  HeldValues held;
  for (const auto& column : streamed_columns(plan))
    held.per_point_in_flight += static_cast<double>(column.width);
  for (std::size_t k = 0; k < plan.columns.size(); ++k) {
    const ColumnSpec& column = plan.columns[k];
    // `basin` is held compact (engine/basin_column.hpp): at most 4 bytes a point, half a double.
    // A block becomes compact only once the journal has saved it: until then (in flight) its
    // `basin` is doubles, 4 bytes a point more.
    if (static_cast<int>(k) == plan.map.basin) {
      held.per_point_kept += 0.5 * static_cast<double>(column.width);
      held.per_point_in_flight += 0.5 * static_cast<double>(column.width);
    }
    if (!column.internal) continue;
    // The recurrence mapper's record and reason: a saved block keeps only its distinct entries
    // and its counts per reason (engine/recurrence/lane_records.hpp), but only where they cost
    // less than these per-point columns, which are thus the most it holds.
    if (static_cast<int>(k) == plan.map.undecided_reason) held.per_block_kept += kUndecidedReasons;
    if (column.per_block) held.per_block_kept += static_cast<double>(column.width);
    else held.per_point_kept += static_cast<double>(column.width);
  }
  return held;
}

// A final write this large takes long enough on a cluster file system to be announced.
constexpr double kAnnouncedWriteBytes = 256.0 * 1024 * 1024;

// Collective: every rank runs the same build on the same spec, hence deals the same blocks. A
// job mixing builds (a stale binary on one node's local disk) would otherwise write a file
// whose cells come from different programs.
void check_same_run(const std::string& run_id, const Comm& c) {
  std::string rank0_id = run_id;
  broadcast(c.comm, rank0_id);
  agreed(c.comm, [&] {
    if (rank0_id != run_id)
      throw std::runtime_error("this rank runs another build or spec than rank 0 (" +
                               build_identity() + "); every rank must run the same program");
  });
}

// Collective: the blocks of all ranks cover the grid exactly once. The block plan guarantees
// it; this makes a file with unwritten cells impossible even if the plan were broken.
void check_every_point_computed(const std::vector<std::unique_ptr<BlockResults>>& results,
                                std::int64_t points, const Comm& c) {
  std::int64_t local = 0;
  for (const auto& r : results) local += r ? r->range.end - r->range.begin : 0;
  std::int64_t total = local;
  allreduce(c.comm, &total, 1, MPI_INT64_T, MPI_SUM);
  if (total != points)
    throw CollectiveError(fmt::format("internal error: the ranks computed {} points of a grid of "
                                      "{}; no output written, the journal is kept",
                                      total, points));
}

std::string gib(double bytes) { return fmt::format("{:.3g} GiB", bytes / (1024.0 * 1024 * 1024)); }

// Collective. Refuses, before any work, a run whose results cannot fit. A rank holds its blocks
// in flight (being computed by its threads, queued for the journal, queued for the output: at
// most about two per thread and the journal's queue) and, on a basin map, each block's labels
// (compact: engine/basin_column.hpp) and internal columns until the end (the recurrence
// mapper's at most per point: engine/recurrence/lane_records.hpp); rank 0 also reads one
// band of the map back from the file at a time for the statistics (summary_bytes_on_rank0). Ranks on one node share its memory (counted per node, against that node's
// budget); at the end the disk holds the journal and the file at once.
void check_resources(const RunPlan& plan, std::int64_t local_points, std::int64_t local_blocks,
                     std::int64_t block_size, std::int64_t blocks,
                     const StartDecision& decision, const SweepOptions& options, const Comm& c) {
  const HeldValues held = held_values(plan);
  const double in_flight_blocks = std::min<double>(
      static_cast<double>(local_blocks),
      2.0 * omp_get_max_threads() + static_cast<double>(JournalWriter::kMaxQueued));
  double node_bytes =
      (in_flight_blocks * static_cast<double>(block_size) * held.per_point_in_flight +
       static_cast<double>(local_points) * held.per_point_kept +
       static_cast<double>(local_blocks) * held.per_block_kept) * sizeof(double);
  // Every rank's plan holds the grid's axes and sample times (on a 1-D plane, an axis is the
  // grid; the output's layout only views them), and the energy trap's record of the wells a
  // copy of the q values.
  double axis_values = static_cast<double>(plan.sample_times.size());
  for (const auto& axis : plan.spec.axes) axis_values += static_cast<double>(axis.values.size());
  node_bytes += axis_values * sizeof(double) + energy_trap_record_bytes(plan);
  // Rank 0 writes `basin` through a batch, freed before it reads the map back a band at a time.
  if (c.rank == 0 && plan.map.basin >= 0)
    node_bytes += std::max(summary_bytes_on_rank0(plan), basin_batch_bytes(plan));
  MPI_Comm node = MPI_COMM_NULL;
  if (!serial(c.comm))
    MPI_Comm_split_type(c.comm, MPI_COMM_TYPE_SHARED, c.rank, MPI_INFO_NULL, &node);
  allreduce(node, &node_bytes, 1, MPI_DOUBLE, MPI_SUM);
  const int node_ranks = size_of(node);
  if (!serial(node)) MPI_Comm_free(&node);
  agreed(c.comm, [&] {
    const MemoryBudget budget = memory_budget();
    if (node_bytes > 0.8 * budget.bytes)
      throw InputError(fmt::format(
          "the results need {} of memory on this node ({} rank(s); blocks of {} points in "
          "flight, {} values per point kept to the end) but {} is available ({}); use a "
          "coarser grid, fewer measures, a larger trajectory.every or more nodes",
          gib(node_bytes), node_ranks, block_size, held.per_point_kept, gib(budget.bytes),
          budget.source));
    if (c.rank != 0) return;
    const double output_bytes = file_bytes(plan) + 65536.0;  // + HDF5 metadata
    const double journal_bytes = file_bytes(plan) + static_cast<double>(blocks) * 256;
    const double needed =
        output_bytes + std::max(0.0, journal_bytes - static_cast<double>(decision.journal_bytes));
    const auto directory = std::filesystem::absolute(options.output).parent_path();
    std::error_code error;
    const auto space = std::filesystem::space(directory, error);
    if (error)
      throw InputError("cannot write the output '" + options.output + "': " + error.message());
    if (needed > 0.95 * static_cast<double>(space.available))
      throw InputError(fmt::format(
          "the output and its journal need about {} but {} has {} free (the file {}, the "
          "journal of finished blocks {}, both on disk until the file is in place)",
          gib(needed), directory.string(), gib(static_cast<double>(space.available)),
          gib(output_bytes), gib(journal_bytes)));
  });
}

// Rank 0: the output is in place (or the run was stopped and its journal is of no use), so
// whatever happens here changes nothing of the outcome.
void remove_finished_journal(Journal& journal) {
  try {
    journal.remove();
  } catch (const std::exception& e) {
    log("contactsweep: warning: the output is complete but its journal '{}' could not be "
        "removed: {}", journal.directory(), e.what());
  }
}

// Test hook (CONTACTSWEEP_TEST_KILL=STAGE[:N][@RANK][/SIGNAL]): the process kills itself with
// SIGKILL at a chosen point, so that tests can interrupt real runs deterministically. Stages:
// `block` (after the N-th saved block of this rank), `write` (HDF5 file open, nothing
// committed), `commit` (output in place, journal not yet removed). @RANK limits it to one rank
// (a rank that dies while the others go on). /term or /int sends the process SIGTERM or SIGINT
// instead, which it handles (stop_signal.hpp) and goes on; /stop sends SIGSTOP, and the process
// waits for the test's SIGCONT: a rank far slower than the others.
void test_kill_point(const char* stage, int rank, std::int64_t count = 0) {
  static const char* spec = std::getenv("CONTACTSWEEP_TEST_KILL");
  if (spec == nullptr) return;
  std::string s(spec);
  int signal = SIGKILL;
  if (auto slash = s.find('/'); slash != std::string::npos) {
    const std::string name = s.substr(slash + 1);
    signal = name == "int" ? SIGINT : name == "stop" ? SIGSTOP : SIGTERM;
    s = s.substr(0, slash);
  }
  auto at_rank = s.find('@');
  if (at_rank != std::string::npos && std::stoi(s.substr(at_rank + 1)) != rank) return;
  s = s.substr(0, at_rank);
  auto colon = s.find(':');
  std::int64_t at = colon == std::string::npos ? 0 : std::stoll(s.substr(colon + 1));
  // kill(), not raise(): a signal to the process, as a batch system sends it, taken by any
  // thread.
  if (s.substr(0, colon) == stage && count == at) ::kill(::getpid(), signal);
}

// Collective: whether any rank received a stop signal (stop_signal.hpp). If one did, every rank
// throws StoppedBySignal together: the blocks finished are in the journal (every rank's journal
// writer has finished), which stays for --resume; the temporary output is removed as the
// exception leaves run_sweep (OpenOutput). Checked after the block loop and again before the
// final write; a signal during the write is ignored (the write completes, or a second signal
// ends the process at once): the journal then holds every block.
void stop_if_signalled(const Journal& journal, std::int64_t local_blocks, const Comm& c) {
  int signal = stop_signal();
  allreduce(c.comm, &signal, 1, MPI_INT, MPI_MAX);
  if (signal == 0) return;
  std::int64_t blocks = local_blocks;
  allreduce(c.comm, &blocks, 1, MPI_INT64_T, MPI_SUM);
  std::int64_t saved = -1;  // rank 0 holds the journal's lock: it counts what is there
  if (c.rank == 0) {
    try {
      saved = journal.inspect().block_files;
    } catch (const std::exception&) {
    }
  }
  bcast(c.comm, &saved, 1, MPI_INT64_T, 0);
  throw StoppedBySignal(
      signal, fmt::format("stopped by {}; {}{} blocks saved in {}; run again with --resume to "
                          "continue",
                          stop_signal_name(signal), saved >= 0 ? fmt::format("{} of ", saved) : "",
                          blocks, journal.directory()));
}

// The run's measures as formulas (measures_source) under a name of their own (MeasuresCode):
// kMeasuresStruct and the SHA-256 of their text.
MeasuresCode measures_code(const RunPlan& plan) {
  if (!has_measure_formulas(plan.spec.measures)) return {};
  const std::string text = measures_source(plan.spec.measures, plan.scene, kMeasuresStruct);
  const std::string name = kMeasuresStruct + sha256_hex(text, 32);
  return {measures_source(plan.spec.measures, plan.scene, name), name};
}

// The scene's header and struct for a kernel built at run time: scene.K's generated one, or a
// built-in scene's (its header in the snapshot).
SceneSource scene_source(const RunPlan& plan) {
  return plan.spec.custom ? SceneSource{plan.spec.custom->header, plan.spec.custom->struct_name}
                          : builtin_scene_source(plan.scene.name);
}

// Builds (or finds cached) the kernel `source` with its entry point, and says so; `what` names
// it in the log. A K's basin map that can find attractors other than fixed points
// (may_need_orbits) describes them with the orbit kernel, built after the map: compiled now
// instead, beside this one, a second compiler on the second core (a first map 2.3 -> 1.7 s on
// two cores: docs/performance.md).
void* kernel_with_orbit(const RunPlan& plan, const SceneSource& scene, const std::string& source,
                        const char* entry, const std::string& what, const SweepOptions& options,
                        MPI_Comm comm) {
  std::optional<std::string> orbit_source;
  if (plan.spec.custom && plan.map.basin >= 0 && may_need_orbits(plan))
    orbit_source = orbit_kernel_source(scene.header, scene.struct_name, plan.spec.method);
  BuiltKernel built, orbit;
  void* found = prepare_kernel(source, entry, comm, &built,
                               orbit_source ? &*orbit_source : nullptr, &orbit);
  if (built.compiled && !options.quiet && rank_of(comm) == 0)
    log("contactsweep: built the kernel of {} in {:.1f} s (cached: {})", what, built.seconds,
        built.library);
  if (orbit.compiled && !options.quiet && rank_of(comm) == 0)
    log("contactsweep: built the orbit kernel of scene.K beside it, to describe its attractors, "
        "in {:.1f} s (cached: {})", orbit.seconds, orbit.library);
  return found;
}

// A custom scene's kernel, compiled once per node and cached (kernel_build/), before anything
// is written: a failed build leaves no journal and no file. A built-in scene goes through it too
// when the run has the lyapunov tangent or measures as formulas (observe, stop): the built-in
// kernels are compiled without them.
// Its runner holds the basin mappers the slices' plans use (one plan per step size) and no others.
KernelFn custom_kernel(const RunPlan& plan, const std::vector<std::unique_ptr<RunPlan>>& slices,
                       const SweepOptions& options, MPI_Comm comm) {
  const SceneSource scene = scene_source(plan);
  KernelChoice choice{plan.spec.method, plan.carry, plan.grid.uniform_parameters()};
  choice.mappers = mappers_of(plan);
  // The tangent's and the stop's advances always build the extension (BlockRunner): their
  // kernels say true whatever they sample, so they are one kernel either way.
  choice.dense_output = !plan.method.adaptive || plan.carry.tangent ||
                        plan.spec.measures.stop.has_value() || samples_inside_steps(plan);
  for (const auto& slice : slices) {
    choice.mappers = choice.mappers | mappers_of(*slice);
    choice.dense_output = choice.dense_output || samples_inside_steps(*slice);
  }
  choice.measures = measures_code(plan);
  const std::string what = plan.spec.custom       ? "scene.K"
                           : plan.carry.tangent   ? "scene " + plan.scene.name + " with lyapunov"
                                                  : "scene " + plan.scene.name + " with its measures";
  return reinterpret_cast<KernelFn>(kernel_with_orbit(
      plan, scene, kernel_source(scene.header, scene.struct_name, choice), kKernelEntry, what,
      options, comm));
}

// A K's step kernel (engine/step_kernel.hpp) for runs the program's own runner can make
// (runs_on_step_kernel): its step loop and per-lane functions alone, a fraction of a whole
// kernel's compile (docs/performance.md); with the run's measures as formulas where it has them
// (a built-in scene's run with observe gets one too). Compiled once per node and cached, as
// custom_kernel, with a basin map's orbit kernel beside it.
const StepKernel* step_kernel(const RunPlan& plan, const SweepOptions& options, MPI_Comm comm) {
  const SceneSource scene = scene_source(plan);
  const MeasuresCode measures = measures_code(plan);
  const std::string what =
      plan.spec.custom ? "scene.K" : "scene " + plan.scene.name + " with its measures";
  void* entry = kernel_with_orbit(
      plan, scene,
      step_kernel_source(scene.header, scene.struct_name, plan.carry,
                         plan.grid.uniform_parameters(), uses_energy_trap(plan), measures),
      kStepKernelEntry, what, options, comm);
  const StepKernel* kernel = reinterpret_cast<StepKernelEntry>(entry)(plan.spec.method.c_str());
  if (kernel == nullptr)
    throw std::logic_error("the step kernel of " + what + " has no table for " + plan.spec.method);
  check_step_kernel(*kernel, plan);
  return kernel;
}

// The orbit kernel of the run's scene and method (kernel_source.hpp), built after the map when
// its table needs orbits: every rank has the same table, so all or none get here.
OrbitFn orbit_kernel(const RunPlan& plan, const SweepOptions& options, MPI_Comm comm) {
  const SceneSource scene = scene_source(plan);
  BuiltKernel built;
  void* entry = prepare_kernel(orbit_kernel_source(scene.header, scene.struct_name, plan.spec.method),
                               kOrbitEntry, comm, &built);
  if (built.compiled && !options.quiet && rank_of(comm) == 0)
    log("contactsweep: built the orbit kernel of {} to describe its attractors in {:.1f} s "
        "(cached: {})",
        plan.spec.custom ? "scene.K" : "scene " + plan.scene.name, built.seconds, built.library);
  return reinterpret_cast<OrbitFn>(entry);
}

// A RunControl sees the reporter of the loop, and only while it lives.
class Attached {
 public:
  Attached(RunControl* control, const ProgressReporter& progress) : control_(control) {
    if (control_ != nullptr) control_->attach(&progress);
  }
  ~Attached() {
    if (control_ != nullptr) control_->attach(nullptr);
  }
  Attached(const Attached&) = delete;
  Attached& operator=(const Attached&) = delete;

 private:
  RunControl* control_;
};

}  // namespace

SweepSummary run_sweep(const RunSpec& spec, const SweepOptions& options, MPI_Comm comm) {
  Comm c(comm);
  const SceneInfo* scene = &scene_of(spec);
  const MethodInfo* method = find_method(spec.method);
  RunPlan plan(spec, *scene, *method);  // the whole grid: datasets, layout
  check_output_names(plan);  // before the kernel is built and any work is done
  std::vector<std::unique_ptr<RunSpec>> slice_specs;
  auto slices = step_size_slices(spec, *scene, *method, slice_specs);
  std::vector<const RunPlan*> slice_plans;
  for (const auto& slice : slices) slice_plans.push_back(slice.get());
  SweepSummary summary;
  summary.points = plan.grid.size();

  // The start is decided before any kernel is built: an output that needs --force, a --resume
  // of another spec's output or a run that is already complete is answered at once, not after
  // seconds of compiling a K (the journal's lock is held meanwhile; a failed build leaves none).
  const std::int64_t block_size = choose_block_size(plan.grid.size(), spec.steps);
  const std::string run_id = run_identity(spec.spec_text, plan.grid.size(), block_size);
  check_same_run(run_id, c);
  Journal journal(options.output, run_id);
  const StartDecision decision = agreed_start(spec, options, journal, run_id, comm);
  if (decision.start == Start::complete) {
    if (c.rank == 0 && decision.remove_journal) remove_finished_journal(journal);
    summary.already_complete = true;
    return summary;
  }
  // The memory and disk checks too: a run they refuse compiles nothing (and caches nothing).
  auto blocks = my_blocks(slices, block_size, c);
  std::int64_t local_points = 0;
  for (const auto& b : blocks) local_points += b.range.end - b.range.begin;
  check_resources(plan, local_points, static_cast<std::int64_t>(blocks.size()), block_size,
                  static_cast<std::int64_t>(blocks.size()) * c.size, decision, options, c);
  if (runs_on_step_kernel(slice_plans)) {
    const StepKernel* kernel = step_kernel(plan, options, comm);
    for (auto& slice : slices) slice->step_kernel = kernel;
  } else if (spec.custom || plan.carry.tangent || has_measure_formulas(spec.measures)) {
    const KernelFn kernel = custom_kernel(plan, slices, options, comm);
    for (auto& slice : slices) slice->custom_kernel = kernel;
  }
  auto start_time = std::chrono::steady_clock::now();
  if (decision.start == Start::fresh)
    agreed(comm, [&] {
      if (c.rank == 0)
        journal.start({run_id, build_identity(), plan.grid.size(), block_size,
                       decision.replace_output, spec.spec_text});
    });

  ProgressReporter progress(local_points, plan.grid.size(), spec.steps,
                            !options.quiet && c.rank == 0 && options.control == nullptr);
  Attached attached(options.control, progress);
  const auto stop_requested = [control = options.control] {
    return control != nullptr && control->stop_requested();
  };
  OutputOptions output_options{options.output, options.command_line, decision.replace_output,
                               [&] { test_kill_point("write", c.rank); }, nullptr, {}};
  OpenOutput output;  // destroyed last on a failure: removes the temporary file
  open_output(plan, output_options, output, comm);
  std::vector<std::unique_ptr<BlockResults>> results(blocks.size());
  std::atomic<std::int64_t> computed{0};
  StatusCounts statuses{};
  std::exception_ptr failure;
  FailureWatch watch(comm);
  BlockStream stream(streamed_columns(plan), output.file ? &*output.file : nullptr,
                     [&] { watch.report_failure(); }, comm);
  // Declared after `results` and `stream`: destroyed first, so it never saves or hands over a
  // block that is gone. A saved block goes on to the output: the journal is done with it.
  JournalWriter journal_writer(
      journal, [&](std::int64_t saved) { test_kill_point("block", c.rank, saved); },
      [&] { watch.report_failure(); },  // no thread of any rank starts another block
      [&](const BlockResults& saved) {
        compact_basin(plan, const_cast<BlockResults&>(saved));  // saved: held compact from now
        stream.add(const_cast<BlockResults&>(saved));
      });
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    if (!watch.stop() && !stop_requested()) {
      try {
        const std::int64_t n = blocks[i].range.end - blocks[i].range.begin;
        results[i] = std::make_unique<BlockResults>(blocks[i].range, plan.columns);
        results[i]->in_flight_steps = progress.in_flight_steps();
        const bool loaded = decision.start == Start::resume && journal.load(*results[i]);
        if (!loaded) run_block(*blocks[i].plan, *results[i]);
        count_statuses(*results[i], plan.map.status, statuses);
        if (loaded) {
          compact_basin(plan, *results[i]);
          stream.add(*results[i]);
        } else {
          journal_writer.submit(*results[i]);
          computed += n;
        }
        progress.add(n, !loaded);
      } catch (...) {
#pragma omp critical(sweep_failure)
        if (!failure) failure = std::current_exception();
        watch.report_failure();  // no thread of any rank starts another block
      }
    }
    if (omp_get_thread_num() == 0) {
      watch.poll();
      stream.poll();
    }
  }
  try {
    journal_writer.finish();  // every computed block saved, hence handed to the stream
  } catch (...) {
    if (!failure) failure = std::current_exception();
    watch.report_failure();
  }
  stream.finish([&] { watch.poll(); });  // rank 0 has written every block it was sent
  if (!failure && stream.failure()) failure = stream.failure();
  watch.finish();
  throw_if_any_failed(comm, failure);
  stop_if_signalled(journal, static_cast<std::int64_t>(blocks.size()), c);
  // Serial only (RunControl): no other rank to agree with. The caller (the Python module) has
  // no --resume, and a journal resumes only under the build that wrote it: nobody could use
  // it, and it would refuse the next run to this output. Removed.
  if (stop_requested()) {
    remove_finished_journal(journal);  // a failure to remove it is a warning, as there
    throw Interrupted("stopped on request; nothing written");
  }
  check_every_point_computed(results, plan.grid.size(), c);
  std::optional<BasinSummary> basins;
  if (plan.map.basin >= 0) {
    basins = summarise_basins(plan, results, comm);
    // Each attractor described (attractor_analysis.hpp), its orbit kernel built first when it
    // needs one; rank 0, which writes the file, integrates.
    OrbitFn orbit = nullptr;
    // A table of fixed points may need it all the same, where the Jacobian does not apply at
    // one (fixed_point_exponent.hpp): may_need_orbits could not tell before the map, so it is
    // built here, on every rank alike (the same table, the same exact arithmetic).
    if (needs_orbits(plan, basins->table, &fixed_point_linearisation))
      orbit = orbit_kernel(plan, options, comm);
    const auto analysis_start = std::chrono::steady_clock::now();
    agreed(comm, [&] {
      // The table's fixed points get their exact λ₁ from K's formula (fixed_point_exponent.hpp),
      // evaluated once as the table was merged (the table holds it: linearisation_of).
      if (c.rank == 0)
        basins->analysis =
            analyse_attractors(plan, basins->table, orbit, &fixed_point_linearisation);
    });
    if (orbit != nullptr && !options.quiet && c.rank == 0)
      log("contactsweep: described {} attractor(s) in {:.3f} s", basins->table.size(),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - analysis_start).count());
  }

  // A signal during the attractors' description: stopped before the write. From here on one is
  // ignored.
  stop_if_signalled(journal, static_cast<std::int64_t>(blocks.size()), c);
  if (!options.quiet && c.rank == 0 && file_bytes(plan) >= kAnnouncedWriteBytes)
    log("contactsweep: computed every point; completing {} ({})", options.output,
        gib(file_bytes(plan)));
  // A failure here is thrown on every rank; the journal stays for --resume.
  output_options.basins = basins ? &*basins : nullptr;
  if (basins)
    output_options.statistics = [&](const OutputFile& file) {
      const std::string name = plan.columns[static_cast<std::size_t>(plan.map.basin)].dataset.name;
      add_statistics(plan, *basins, [&](std::int64_t begin, std::int64_t end, BasinLabel* out) {
        file.read(name, {begin, end}, out);
      });
    };
  write_output(plan, results, output_options, output, comm);
  test_kill_point("commit", c.rank);
  if (c.rank == 0) remove_finished_journal(journal);
  if (basins && c.rank == 0 && !options.quiet) log("contactsweep: {}", describe(*basins));

  std::int64_t lane_steps = 0;
  for (const auto& r : results) lane_steps += r->lane_steps;
  std::int64_t counts[6] = {statuses[0].load(), statuses[1].load(), statuses[2].load(),
                            statuses[3].load(), computed.load(), lane_steps};
  allreduce(comm, counts, 6, MPI_INT64_T, MPI_SUM);
  summary.flagged_diverged = counts[0];
  summary.flagged_breakdown = counts[1];
  summary.flagged_non_finite = counts[2];
  summary.flagged_undefined_at_start = counts[3];
  summary.computed_points = counts[4];
  summary.lane_steps = counts[5];
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return summary;
}

}  // namespace cs
