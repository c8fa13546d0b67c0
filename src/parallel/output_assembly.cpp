#include "parallel/output_assembly.hpp"

#include <omp.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>

#include "engine/basin_column.hpp"
#include "formula/custom_scene.hpp"
#include "io/output_file.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "version.hpp"

namespace cs {
namespace {

// Column k's dataset as written: `basin` takes the type its labels need (BasinSummary), and
// numbered labels where the scene's label rule could not apply have no flags.
DatasetSpec written_dataset(const RunPlan& plan, const OutputOptions& options, std::size_t k) {
  DatasetSpec dataset = plan.columns[k].dataset;
  if (options.basins && static_cast<int>(k) == plan.map.basin) {
    dataset.type = options.basins->label_type;
    if (!options.basins->labels.by_rule) {
      dataset.long_name = kNumberedBasinLongName;
      dataset.flag_values.clear();
      dataset.flag_meanings.clear();
    }
  }
  return dataset;
}

// The file's layout; its grid axes and sample times are views of the plan's, so it must not
// outlive the plan (every layout here is made, used and dropped within a call).
FileLayout make_layout(const RunPlan& plan, const OutputOptions& options, int ranks,
                       int threads) {
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
    layout.axes.push_back({axis.name, CoordinateValues::borrowed(axis.values), long_name, ""});
  }
  if (plan.samples > 0)
    layout.time = CoordinateSpec{"t", CoordinateValues::borrowed(plan.sample_times), "time", "time"};
  for (std::size_t k = 0; k < plan.columns.size(); ++k)
    if (!plan.columns[k].internal) layout.datasets.push_back(written_dataset(plan, options, k));
  if (options.basins) add_to_layout(*options.basins, plan, layout);
  auto& text = layout.text_attributes;
  text["title"] = plan.spec.title;
  text["spec"] = plan.spec.spec_text;
  text["scene"] = plan.scene.name;
  text["hamiltonian"] = plan.scene.hamiltonian;
  if (plan.spec.custom) text["K"] = plan.spec.custom->formula.text;
  text["method"] = plan.method.name;
  text["contactsweep_version"] = kVersion;
  text["Conventions"] = "CF-1.8";
  text["history"] = options.command_line;
  auto& number = layout.number_attributes;
  const bool h_axis = !plan.spec.axes.empty() && plan.spec.axes.front().is_step_size;
  const double nan = std::numeric_limits<double>::quiet_NaN();  // h varies: see coordinate h
  number["h"] = h_axis ? nan : plan.spec.h;
  number["t_start"] = plan.spec.t_start;
  number["t_end"] = plan.spec.t_end;
  // An adaptive method's lanes take steps of their own: no step count, h their first step.
  number["steps"] = h_axis || plan.method.adaptive ? nan : static_cast<double>(plan.spec.steps);
  if (plan.method.adaptive) {
    number["rtol"] = plan.spec.rtol;
    number["atol"] = plan.spec.atol;
  }
  number["mpi_ranks"] = ranks;
  number["omp_threads"] = threads;  // the largest of any rank: ranks may differ
  return layout;
}

// One block's values of one column, as rank 0 receives it.
struct ColumnPiece {
  PointRange range;
  std::vector<double> values;
};

// MPI counts are int: long buffers go in pieces of at most 2^27 elements.
constexpr std::size_t kMessageElements = std::size_t{1} << 27;

// Block by block, straight from the results: no rank holds a second copy of a column (the
// memory check counts the results once).
void send_column(const RunPlan& plan, const std::vector<std::unique_ptr<BlockResults>>& results,
                 std::size_t k, MPI_Comm comm) {
  auto blocks = static_cast<std::int64_t>(results.size());
  MPI_Send(&blocks, 1, MPI_INT64_T, 0, 0, comm);
  for (const auto& block : results) {
    const ExpandedBasin labels(plan, *block);  // `basin`: held compact (basin_column.hpp)
    const std::vector<double>& values = block->columns[k];
    std::int64_t header[3] = {block->range.begin, block->range.end,
                              static_cast<std::int64_t>(values.size())};
    MPI_Send(header, 3, MPI_INT64_T, 0, 0, comm);
    for (std::size_t done = 0; done < values.size(); done += kMessageElements)
      MPI_Send(values.data() + done,
               static_cast<int>(std::min(kMessageElements, values.size() - done)), MPI_DOUBLE,
               0, 0, comm);
  }
}

std::int64_t receive_block_count(int from, MPI_Comm comm) {
  std::int64_t blocks = 0;
  MPI_Recv(&blocks, 1, MPI_INT64_T, from, 0, comm, MPI_STATUS_IGNORE);
  return blocks;
}

ColumnPiece receive_piece(int from, MPI_Comm comm) {
  std::int64_t header[3];
  MPI_Recv(header, 3, MPI_INT64_T, from, 0, comm, MPI_STATUS_IGNORE);
  ColumnPiece piece{{header[0], header[1]}, std::vector<double>(static_cast<std::size_t>(header[2]))};
  for (std::size_t done = 0; done < piece.values.size(); done += kMessageElements)
    MPI_Recv(piece.values.data() + done,
             static_cast<int>(std::min(kMessageElements, piece.values.size() - done)),
             MPI_DOUBLE, from, 0, comm, MPI_STATUS_IGNORE);
  return piece;
}

// Gathers consecutive blocks of one column into one write request: blocks that touch merge
// into one box of the file (OutputFile writes box by box), and each HDF5 call has a fixed cost
// (~0.2 ms a block through MPI-IO once; 384 writes for a 512² map). The batch is bounded, so
// memory grows by at most kBatchValues doubles.
class ColumnBatch {
 public:
  // `values`: how many the column holds in all. Its room is taken at once: grown by doubling, a
  // 512² map's batch faulted in twice its size and copied itself six times at the end of the run.
  ColumnBatch(OutputFile& file, const DatasetSpec& dataset, std::size_t values)
      : file_(file), dataset_(dataset) {
    values_.reserve(std::min(values, kBatchValues));
  }
  void add(PointRange range, const std::vector<double>& values) {
    ranges_.push_back(range);
    values_.insert(values_.end(), values.begin(), values.end());
    if (values_.size() >= kBatchValues) flush();
  }
  void flush() {
    if (ranges_.empty()) return;
    write_values(file_, dataset_, ranges_, values_);
    ranges_.clear();
    values_.clear();
  }

  static constexpr std::size_t kBatchValues = std::size_t{1} << 23;  // 64 MiB

 private:
  OutputFile& file_;
  const DatasetSpec dataset_;
  std::vector<PointRange> ranges_;  // ascending: blocks come in order from each rank
  std::vector<double> values_;
};

}  // namespace

void check_output_names(const RunPlan& plan) {
  FileLayout layout = make_layout(plan, OutputOptions{}, 1, 1);
  if (plan.map.basin >= 0) add_names_to_layout(plan, layout);
  const std::string name = repeated_name(layout);
  if (!name.empty())
    throw InputError("the output would hold two datasets named '" + name +
                     "' (a grid axis or parameter and a measure's dataset); rename the parameter");
}

double basin_batch_bytes(const RunPlan& plan) {
  if (plan.map.basin < 0) return 0.0;
  const auto width = static_cast<std::size_t>(plan.columns[static_cast<std::size_t>(plan.map.basin)].width);
  const auto points = static_cast<std::size_t>(plan.grid.size());
  return static_cast<double>(std::min(points * width, ColumnBatch::kBatchValues)) * sizeof(double);
}

static bool is_streamed(const RunPlan& plan, std::size_t k) {
  return !plan.columns[k].internal && static_cast<int>(k) != plan.map.basin;
}

std::vector<BlockStream::Column> streamed_columns(const RunPlan& plan) {
  std::vector<BlockStream::Column> columns;
  for (std::size_t k = 0; k < plan.columns.size(); ++k)
    if (is_streamed(plan, k))
      columns.push_back({static_cast<int>(k), plan.columns[k].width, plan.columns[k].dataset});
  return columns;
}

void open_output(const RunPlan& plan, const OutputOptions& options, OpenOutput& output,
                 MPI_Comm comm) {
  output.ranks = size_of(comm);
  output.threads = omp_get_max_threads();
  allreduce(comm, &output.threads, 1, MPI_INT, MPI_MAX);
  OutputOptions early = options;
  early.basins = nullptr;  // known at the end: complete() adds them
  agreed(comm, [&] {
    if (rank_of(comm) == 0)
      output.file.emplace(options.path, make_layout(plan, early, output.ranks, output.threads),
                          OutputFile::DatasetsFirst{});
  });
}

void write_output(const RunPlan& plan, const std::vector<std::unique_ptr<BlockResults>>& results,
                  const OutputOptions& options, OpenOutput& output, MPI_Comm comm) {
  const int rank = rank_of(comm), ranks = size_of(comm);
  // Rank 0: after a failure it stops writing but goes on receiving, so that no sender waits.
  std::optional<OutputFile>& file = output.file;
  std::exception_ptr failure;
  auto attempt = [&](auto&& step) {
    if (failure) return;
    try {
      step();
    } catch (...) {
      failure = std::current_exception();
      file.reset();  // removes the temporary file
    }
  };
  // `basin` in its final type first: its statistics are read back from the file.
  if (rank == 0)
    attempt([&] { file->complete_datasets(make_layout(plan, options, output.ranks, output.threads)); });
  for (std::size_t k = 0; k < plan.columns.size(); ++k) {
    const DatasetSpec dataset = written_dataset(plan, options, k);
    if (plan.columns[k].internal || is_streamed(plan, k)) continue;
    if (rank != 0) {
      send_column(plan, results, k, comm);
      continue;
    }
    std::optional<ColumnBatch> batch;
    attempt([&] {
      batch.emplace(*file, dataset,
                    static_cast<std::size_t>(plan.grid.size() * plan.columns[k].width));
    });
    for (const auto& block : results) {
      const ExpandedBasin labels(plan, *block);
      attempt([&] { batch->add(block->range, block->columns[k]); });
    }
    attempt([&] { batch->flush(); });  // one batch per rank: ranges ascend within it
    for (int from = 1; from < ranks; ++from) {
      for (std::int64_t b = receive_block_count(from, comm); b > 0; --b) {
        const ColumnPiece piece = receive_piece(from, comm);
        attempt([&] { batch->add(piece.range, piece.values); });
      }
      attempt([&] { batch->flush(); });
    }
  }
  if (rank == 0) {
    attempt([&] {
      if (options.statistics) options.statistics(*file);
      file->complete(make_layout(plan, options, output.ranks, output.threads));
    });
    attempt([&] {
      if (options.before_commit) options.before_commit();
      file->commit(options.replace_existing);
    });
  }
  throw_if_any_failed(comm, failure);
}

}  // namespace cs
