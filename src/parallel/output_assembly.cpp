#include "parallel/output_assembly.hpp"

#include <omp.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>

#include "io/output_file.hpp"
#include "parallel/agreement.hpp"
#include "version.hpp"

namespace cs {
namespace {

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
  number["mpi_ranks"] = ranks;
  number["omp_threads"] = threads;  // the largest of any rank: ranks may differ
  return layout;
}

// One rank's values of one column: its point ranges and their values back to back.
struct ColumnPiece {
  std::vector<PointRange> ranges;
  std::vector<double> values;
};

ColumnPiece piece_of(const std::vector<std::unique_ptr<BlockResults>>& results, std::size_t k) {
  ColumnPiece piece;
  for (const auto& block : results) {
    piece.ranges.push_back(block->range);
    const auto& column = block->columns[k];
    piece.values.insert(piece.values.end(), column.begin(), column.end());
  }
  return piece;
}

// MPI counts are int: long buffers go in pieces of at most 2^27 elements.
constexpr std::int64_t kMessageElements = std::int64_t{1} << 27;

void send_piece(const ColumnPiece& piece, MPI_Comm comm) {
  std::int64_t sizes[2] = {static_cast<std::int64_t>(piece.ranges.size()),
                           static_cast<std::int64_t>(piece.values.size())};
  MPI_Send(sizes, 2, MPI_INT64_T, 0, 0, comm);
  static_assert(sizeof(PointRange) == 2 * sizeof(std::int64_t));
  for (std::int64_t done = 0; done < 2 * sizes[0]; done += kMessageElements)
    MPI_Send(reinterpret_cast<const std::int64_t*>(piece.ranges.data()) + done,
             static_cast<int>(std::min(kMessageElements, 2 * sizes[0] - done)), MPI_INT64_T, 0,
             0, comm);
  for (std::int64_t done = 0; done < sizes[1]; done += kMessageElements)
    MPI_Send(piece.values.data() + done,
             static_cast<int>(std::min(kMessageElements, sizes[1] - done)), MPI_DOUBLE, 0, 0,
             comm);
}

ColumnPiece receive_piece(int from, MPI_Comm comm) {
  std::int64_t sizes[2];
  MPI_Recv(sizes, 2, MPI_INT64_T, from, 0, comm, MPI_STATUS_IGNORE);
  ColumnPiece piece;
  piece.ranges.resize(static_cast<std::size_t>(sizes[0]));
  piece.values.resize(static_cast<std::size_t>(sizes[1]));
  for (std::int64_t done = 0; done < 2 * sizes[0]; done += kMessageElements)
    MPI_Recv(reinterpret_cast<std::int64_t*>(piece.ranges.data()) + done,
             static_cast<int>(std::min(kMessageElements, 2 * sizes[0] - done)), MPI_INT64_T,
             from, 0, comm, MPI_STATUS_IGNORE);
  for (std::int64_t done = 0; done < sizes[1]; done += kMessageElements)
    MPI_Recv(piece.values.data() + done,
             static_cast<int>(std::min(kMessageElements, sizes[1] - done)), MPI_DOUBLE, from, 0,
             comm, MPI_STATUS_IGNORE);
  return piece;
}

template <class T>
std::vector<T> converted(const std::vector<double>& values) {
  std::vector<T> out(values.size());
  std::transform(values.begin(), values.end(), out.begin(),
                 [](double v) { return static_cast<T>(v); });
  return out;
}

void write_piece(OutputFile& file, const DatasetSpec& dataset, const ColumnPiece& piece) {
  switch (dataset.type) {
    case ElementType::float64: file.write(dataset.name, piece.ranges, piece.values.data()); break;
    case ElementType::int8:
      file.write(dataset.name, piece.ranges, converted<std::int8_t>(piece.values).data());
      break;
    case ElementType::uint8:
      file.write(dataset.name, piece.ranges, converted<std::uint8_t>(piece.values).data());
      break;
  }
}

}  // namespace

void write_output(const RunPlan& plan, const std::vector<std::unique_ptr<BlockResults>>& results,
                  const OutputOptions& options, MPI_Comm comm) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  int threads = omp_get_max_threads();
  MPI_Allreduce(MPI_IN_PLACE, &threads, 1, MPI_INT, MPI_MAX, comm);

  // Rank 0: after a failure it stops writing but goes on receiving, so that no sender waits.
  std::optional<OutputFile> file;
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
  if (rank == 0)
    attempt([&] { file.emplace(options.path, make_layout(plan, options, ranks, threads),
                               MPI_COMM_SELF); });
  for (std::size_t k = 0; k < plan.columns.size(); ++k) {
    const DatasetSpec& dataset = plan.columns[k].dataset;
    if (rank != 0) {
      send_piece(piece_of(results, k), comm);
      continue;
    }
    attempt([&] { write_piece(*file, dataset, piece_of(results, k)); });
    for (int from = 1; from < ranks; ++from) {
      const ColumnPiece piece = receive_piece(from, comm);
      attempt([&] { write_piece(*file, dataset, piece); });
    }
  }
  if (rank == 0) {
    attempt([&] {
      if (options.before_commit) options.before_commit();
      file->commit(options.replace_existing);
    });
  }
  throw_if_any_failed(comm, failure);
}

}  // namespace cs
