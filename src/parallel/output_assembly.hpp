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
#pragma once

#include <mpi.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/results.hpp"
#include "engine/run_plan.hpp"
#include "parallel/basin_summary.hpp"

namespace cs {

struct OutputOptions {
  std::string path;
  std::string command_line;     // the `history` attribute
  bool replace_existing = false;  // --force: the commit may replace a file at `path`
  std::function<void()> before_commit;  // test hook: runs on rank 0 with the file written
  const BasinSummary* basins = nullptr;  // the attractor table and statistics, with `basin`
};

// Before any work: throws InputError if the file would give one name to two of its datasets
// (a K parameter named `status`, `basin`, `attractor`, ... swept as a grid axis).
void check_output_names(const RunPlan& plan);

// Collective. `results` are this rank's blocks in ascending order of their points. Throws a
// CollectiveError on every rank when the file could not be written; no file is then left
// under either name.
void write_output(const RunPlan& plan, const std::vector<std::unique_ptr<BlockResults>>& results,
                  const OutputOptions& options, MPI_Comm comm);

}  // namespace cs
