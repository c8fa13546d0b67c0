// Assembling the result file from every rank's blocks.
//
// Rank 0 writes the HDF5 file alone (HDF5 serial driver); the other ranks send it their results one
// column at a time. Why not parallel HDF5's collective writes: HDF5 does not fail symmetrically.
// A full disk met by one rank inside a collective HDF5 call (a chunk fill, a metadata flush)
// makes that rank return an error while the others wait inside HDF5 for it, and the job hangs
// with no message; nothing outside HDF5 can agree on the failure in time. With one writer no HDF5
// call spans ranks: rank 0 keeps receiving to the end whatever happens, and the outcome is agreed
// afterwards. The price is the write bandwidth of one rank, which for the maps we write (tens
// of MB to a few GB) is seconds against minutes to hours of integration.
//
// The file is opened before the first block (open_output) and most columns are written while
// the run goes on (parallel/block_stream.hpp); what needs every block (`basin`'s labels, the
// attractor table, the statistics) is written at the end (write_output), then the file is put
// in place. Until then it has its temporary name only.
#pragma once

#include <mpi.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/results.hpp"
#include "engine/run_plan.hpp"
#include "parallel/basin_summary.hpp"
#include "parallel/block_stream.hpp"

namespace cs {

struct OutputOptions {
  std::string path;
  std::string command_line;     // the `history` attribute
  bool replace_existing = false;  // --force: the commit may replace a file at `path`
  std::function<void()> before_commit;  // test hook: runs on rank 0 with the file written
  const BasinSummary* basins = nullptr;  // the attractor table and statistics, with `basin`
  // Rank 0, with `basin` written and before the layout is completed: computes the statistics
  // `basins` holds from the file (basin_summary.hpp, add_statistics).
  std::function<void(const OutputFile&)> statistics;
};

// Before any work: throws InputError if the file would give one name to two of its datasets
// (a K parameter named `status`, `basin`, `attractor`, ... swept as a grid axis).
void check_output_names(const RunPlan& plan);

// The temporary file, open on rank 0 (empty elsewhere), and the layout facts every rank shares.
struct OpenOutput {
  std::optional<OutputFile> file;
  int ranks = 1, threads = 1;
};

// Collective, before the first block: rank 0 creates the temporary file with every per-point
// dataset. A failure is thrown on every rank (CollectiveError).
void open_output(const RunPlan& plan, const OutputOptions& options, OpenOutput& output,
                 MPI_Comm comm);

// What rank 0's batch for writing `basin` holds at most, in bytes (freed before the statistics
// read the labels back).
double basin_batch_bytes(const RunPlan& plan);

// The columns written while the run goes on: every written column but `basin`.
std::vector<BlockStream::Column> streamed_columns(const RunPlan& plan);

// Collective. Writes what the stream did not (`basin`, from `results`: this rank's blocks in
// ascending order of their points), then on rank 0 the statistics read back from it
// (options.statistics), the attractor table and statistics, then commits. Throws a
// CollectiveError on every rank when the file could not be written; no file is then left
// under either name.
void write_output(const RunPlan& plan, const std::vector<std::unique_ptr<BlockResults>>& results,
                  const OutputOptions& options, OpenOutput& output, MPI_Comm comm);

}  // namespace cs
