// The journal of a run: finished blocks saved beside the output as they finish, so that a run
// killed at any moment (kill -9, a batch system's wall-time limit, a dead rank) loses nothing
// it finished, and `--resume` continues it — with any number of ranks and threads.
//
// Why not record progress inside the HDF5 file: HDF5 metadata is not safe against a kill in the
// middle of a write, and one corrupt file would lose everything. Instead every block is its own
// small file, written under a temporary name, synced and renamed into place (atomic on POSIX),
// with a checksum; the HDF5 file is only assembled at the end, and the journal is removed once
// the output has been renamed into place.
//
// Layout: OUT.h5.journal/manifest (identity of the run) and block_<begin>.bin per block.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/results.hpp"

namespace cs {

// What makes two runs the same run: same spec text (after --set), same program version, same
// block size (block size changes no bits, but blocks are the journal's unit).
struct RunIdentity {
  std::string spec_text;
  std::string version;
  std::int64_t points = 0;
  std::int64_t block_size = 0;
};

class Journal {
 public:
  explicit Journal(const std::string& output_path);

  const std::string& directory() const { return directory_; }
  bool exists() const;

  // The identity recorded by an earlier run, if a readable manifest is there.
  std::optional<RunIdentity> recorded_identity() const;

  // Rank 0 only: start an empty journal for `id`, replacing any old one.
  void create(const RunIdentity& id) const;

  // Thread-safe: saves a finished block atomically. Throws std::runtime_error on I/O failure.
  void save(const BlockResults& block) const;

  // Loads a saved block into `block` (range and column widths must match); false when the
  // block is missing or damaged (then it is simply computed again).
  bool load(BlockResults& block) const;

  // Rank 0 only, after the output is in place.
  void remove() const;

 private:
  std::string block_path(std::int64_t begin) const;
  std::string directory_;
};

}  // namespace cs
