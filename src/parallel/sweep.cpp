#include "parallel/sweep.hpp"

#include <fmt/core.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include "engine/run_plan.hpp"
#include "io/memory_budget.hpp"
#include "io/output_file.hpp"
#include "io/output_inspect.hpp"
#include "parallel/journal.hpp"
#include "parallel/progress.hpp"
#include "version.hpp"

namespace cs {
namespace {

struct Comm {
  MPI_Comm comm;
  int rank = 0, size = 1;
  explicit Comm(MPI_Comm c) : comm(c) {
    MPI_Comm_rank(c, &rank);
    MPI_Comm_size(c, &size);
  }
};

// Blocks are the unit of load balance: several per thread so that dynamic scheduling can even
// out lanes that stop early, large enough that refilling a tile keeps it full most of the time.
std::int64_t choose_block_size(std::int64_t points, int ranks, int threads) {
  std::int64_t target = points / (static_cast<std::int64_t>(ranks) * threads * 16);
  return std::clamp<std::int64_t>(target, 256, 16384);
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

FileLayout make_layout(const RunPlan& plan, const SweepOptions& options, const Comm& c) {
  FileLayout layout;
  for (const auto& axis : plan.spec.axes) {
    std::string long_name;
    if (axis.is_step_size) {
      long_name = "integrator step size h";
    } else if (axis.is_parameter) {
      for (const auto& p : plan.scene.parameters)
        if (p.name == axis.target) long_name = p.description;
    } else {
      long_name = "initial value of " + axis.target;
    }
    layout.axes.push_back({axis.name, axis.values, long_name, ""});
  }
  if (plan.samples > 0) layout.time = CoordinateSpec{"t", plan.sample_times, "time", "time"};
  for (const auto& column : plan.columns) layout.datasets.push_back(column.dataset);
  auto& text = layout.text_attributes;
  text["title"] = plan.spec.title;
  text["spec"] = plan.spec.spec_text;
  text["scene"] = plan.scene.name;
  text["hamiltonian"] = plan.scene.hamiltonian;
  text["method"] = plan.method.name;
  text["contactsweep_version"] = kVersion;
  text["Conventions"] = "CF-1.8";
  text["history"] = options.command_line;
  auto& number = layout.number_attributes;
  const bool h_axis = !plan.spec.axes.empty() && plan.spec.axes.front().is_step_size;
  const double nan = std::numeric_limits<double>::quiet_NaN();  // h varies: see coordinate h
  number["h"] = h_axis ? nan : plan.spec.h;
  number["t_end"] = plan.spec.t_end;
  number["steps"] = h_axis ? nan : static_cast<double>(plan.spec.steps);
  number["mpi_ranks"] = c.size;
  number["omp_threads"] = omp_get_max_threads();
  return layout;
}

template <class T>
std::vector<T> converted(const std::vector<double>& values) {
  std::vector<T> out(values.size());
  std::transform(values.begin(), values.end(), out.begin(),
                 [](double v) { return static_cast<T>(v); });
  return out;
}

void write_column(OutputFile& file, const ColumnSpec& spec, std::size_t index,
                  const std::vector<std::unique_ptr<BlockResults>>& blocks) {
  std::vector<PointRange> ranges;
  std::vector<double> values;
  for (const auto& b : blocks) {
    ranges.push_back(b->range);
    const auto& col = b->columns[index];
    values.insert(values.end(), col.begin(), col.end());
  }
  switch (spec.dataset.type) {
    case ElementType::float64: file.write(spec.dataset.name, ranges, values.data()); break;
    case ElementType::int8: file.write(spec.dataset.name, ranges, converted<std::int8_t>(values).data()); break;
    case ElementType::uint8: file.write(spec.dataset.name, ranges, converted<std::uint8_t>(values).data()); break;
  }
}

std::int64_t count_status(const std::vector<std::unique_ptr<BlockResults>>& blocks, int column,
                          LaneStatus status) {
  std::int64_t n = 0;
  for (const auto& b : blocks)
    for (double v : b->columns[static_cast<std::size_t>(column)])
      n += v == static_cast<double>(status);
  return n;
}

// Refuses, before any work, a run whose results cannot fit: every rank holds the results of
// its blocks until the end (memory), and the file holds all of them (disk). Trajectories are
// the usual culprit; the message says how much was asked and how much there is.
void check_resources(const RunPlan& plan, const SweepOptions& options, const Comm& c) {
  double values_per_point = 0.0;
  for (const auto& column : plan.columns) values_per_point += static_cast<double>(column.width);
  const double points = static_cast<double>(plan.grid.size());
  const double memory_per_rank = points / c.size * values_per_point * sizeof(double);
  const double file_bytes = points * values_per_point * sizeof(double);
  const double available_memory = memory_budget_bytes();
  auto gib = [](double bytes) { return fmt::format("{:.3g} GiB", bytes / (1024.0 * 1024 * 1024)); };
  // Ranks on one node share its memory; assume all of them do (the safe side on a laptop).
  if (memory_per_rank * c.size > 0.8 * available_memory)
    throw InputError(fmt::format(
        "the results need {} of memory ({} points x {} values) but {} is available; use a "
        "coarser grid, fewer measures or a larger trajectory.every",
        gib(memory_per_rank * c.size), plan.grid.size(), values_per_point, gib(available_memory)));
  auto directory = std::filesystem::absolute(options.output).parent_path();
  std::error_code error;
  auto space = std::filesystem::space(directory, error);
  // access() alone passes a regular file for root, so the parent must be a directory too.
  if (error || !std::filesystem::is_directory(directory) ||
      ::access(directory.c_str(), W_OK) != 0)
    throw InputError("cannot write the output '" + options.output + "': directory '" +
                     directory.string() + "' is missing or not writable");
  if (file_bytes > 0.95 * static_cast<double>(space.available))
    throw InputError(fmt::format("the output needs about {} but {} has {} free", gib(file_bytes),
                                 directory.string(), gib(static_cast<double>(space.available))));
}

// How this invocation relates to what an earlier one left at the output path.
enum class Start { fresh, resume, complete };

// Decides from the file system alone (every rank sees the same), before anything is changed.
Start decide_start(const RunSpec& spec, const SweepOptions& options, const Journal& journal,
                   std::int64_t& block_size) {
  const bool output_exists = std::filesystem::exists(options.output);
  if (options.force) return Start::fresh;
  if (output_exists) {
    if (!options.resume)
      throw InputError("output '" + options.output +
                       "' exists; pass --force to replace it or --resume to continue that run");
    auto spec_text = read_spec_attribute(options.output);
    if (spec_text && *spec_text == spec.spec_text) return Start::complete;
    throw InputError("--resume: output '" + options.output +
                     "' was not made by this spec (after --set); pass --force to replace it");
  }
  if (!journal.exists()) return Start::fresh;
  if (!options.resume)
    throw InputError("an unfinished run of '" + options.output + "' left its journal in '" +
                     journal.directory() +
                     "'; pass --resume to continue it or --force to discard it");
  auto recorded = journal.recorded_identity();
  if (!recorded)
    throw InputError("--resume: '" + journal.directory() +
                     "' has no readable manifest; pass --force to start afresh");
  if (recorded->spec_text != spec.spec_text)
    throw InputError("--resume: the unfinished run in '" + journal.directory() +
                     "' was made by a different spec (after --set); pass --force to discard it");
  if (recorded->version != kVersion)
    throw InputError("--resume: the unfinished run was made by contactsweep " +
                     recorded->version + ", this is " + kVersion +
                     "; results could differ, pass --force to start afresh");
  block_size = recorded->block_size;
  return Start::resume;
}

// Test hook (CONTACTSWEEP_TEST_KILL=STAGE[:N][@RANK]): the process kills itself with SIGKILL at
// a chosen point, so that tests can interrupt real runs deterministically. Stages: `block`
// (after the N-th saved block of this rank), `write` (HDF5 file open, nothing committed),
// `commit` (output in place, journal not yet removed). @RANK limits it to one rank (a rank
// that dies while the others go on).
void test_kill_point(const char* stage, int rank, std::int64_t count = 0) {
  static const char* spec = std::getenv("CONTACTSWEEP_TEST_KILL");
  if (spec == nullptr) return;
  std::string s(spec);
  auto at_rank = s.find('@');
  if (at_rank != std::string::npos && std::stoi(s.substr(at_rank + 1)) != rank) return;
  s = s.substr(0, at_rank);
  auto colon = s.find(':');
  std::int64_t at = colon == std::string::npos ? 0 : std::stoll(s.substr(colon + 1));
  if (s.substr(0, colon) == stage && count == at) std::raise(SIGKILL);
}

}  // namespace

SweepSummary run_sweep(const RunSpec& spec, const SweepOptions& options, MPI_Comm comm) {
  Comm c(comm);
  const SceneInfo* scene = find_scene(spec.scene);
  const MethodInfo* method = find_method(spec.method);
  RunPlan plan(spec, *scene, *method);  // the whole grid: datasets, layout
  std::vector<std::unique_ptr<RunSpec>> slice_specs;
  auto slices = step_size_slices(spec, *scene, *method, slice_specs);
  SweepSummary summary;
  summary.points = plan.grid.size();
  auto start_time = std::chrono::steady_clock::now();

  const int threads = omp_get_max_threads();
  std::int64_t block_size = choose_block_size(plan.grid.size(), c.size, threads);
  check_resources(plan, options, c);
  Journal journal(options.output);
  Start start = decide_start(spec, options, journal, block_size);
  MPI_Barrier(comm);  // every rank has looked before rank 0 changes anything
  if (start == Start::complete) {
    if (c.rank == 0) journal.remove();  // left over if a run was killed right after its commit
    summary.already_complete = true;
    return summary;
  }
  if (start == Start::fresh && c.rank == 0)
    journal.create({spec.spec_text, kVersion, plan.grid.size(), block_size});
  MPI_Barrier(comm);

  auto blocks = my_blocks(slices, block_size, c);
  std::int64_t local_points = 0;
  for (const auto& b : blocks) local_points += b.range.end - b.range.begin;
  ProgressReporter progress(local_points, plan.grid.size(), spec.steps,
                            !options.quiet && c.rank == 0);

  std::vector<std::unique_ptr<BlockResults>> results(blocks.size());
  std::atomic<std::int64_t> saved{0};
  std::string failure;
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    try {
      results[i] = std::make_unique<BlockResults>(blocks[i].range, plan.columns);
      if (start != Start::resume || !journal.load(*results[i])) {
        run_block(*blocks[i].plan, *results[i]);
        journal.save(*results[i]);
        test_kill_point("block", c.rank, ++saved);
      }
      progress.add(blocks[i].range.end - blocks[i].range.begin);
    } catch (const std::exception& e) {
#pragma omp critical(sweep_failure)
      if (failure.empty()) failure = e.what();
    }
  }
  int failed = !failure.empty(), any_failed = 0;
  MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, comm);
  if (failed) throw std::runtime_error(failure);
  if (any_failed) throw std::runtime_error("another rank failed; its message is above");

  {
    OutputFile file(options.output, make_layout(plan, options, c), comm);
    for (std::size_t k = 0; k < plan.columns.size(); ++k)
      write_column(file, plan.columns[k], k, results);
    test_kill_point("write", c.rank);
    file.commit();
  }
  test_kill_point("commit", c.rank);
  MPI_Barrier(comm);
  if (c.rank == 0) journal.remove();

  std::int64_t local[2] = {count_status(results, plan.map.status, LaneStatus::diverged),
                           count_status(results, plan.map.status, LaneStatus::breakdown)};
  std::int64_t global[2];
  MPI_Allreduce(local, global, 2, MPI_INT64_T, MPI_SUM, comm);
  summary.flagged_diverged = global[0];
  summary.flagged_breakdown = global[1];
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return summary;
}

}  // namespace cs
