// The journal of a run: finished blocks saved beside the output as they finish, so that a run
// killed at any moment (kill -9, a batch system's wall-time limit, a dead rank) loses nothing
// it finished, and `--resume` continues it — with any number of ranks and threads.
//
// Why not record progress inside the HDF5 file: HDF5 metadata is not safe against a kill in the
// middle of a write, and one corrupt file would lose everything. Instead every block is its own
// small file, written under a temporary name, synced and renamed into place (atomic on POSIX),
// with a checksum; the HDF5 file is only assembled at the end, and the journal is removed once
// the output is durably in place.
//
// Blocks are only ever combined with blocks of the same run: the manifest and every block carry
// the run's identity (run_identity.hpp: spec, build, block cut), and a block with another
// identity is never loaded. While a run lives, rank 0 holds a lock on the journal, so a second
// run on the same output is refused instead of mixing its blocks in or deleting them.
//
// Layout: OUT.h5.journal/lock (who holds the run), manifest (identity of the run) and
// block_<begin>.bin per block.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "engine/results.hpp"
#include "io/owned_directory.hpp"

namespace cs {

// What the manifest records about the run that owns the journal.
struct JournalManifest {
  std::string run_id;            // run_identity(): stamped on every block
  std::string build;             // build_identity() of the program that started the run
  std::int64_t points = 0;
  std::int64_t block_size = 0;
  bool replaces_output = false;  // started with --force: its commit may replace the output
  std::string spec_text;
};

// What an earlier run left in the journal directory.
struct JournalContents {
  bool directory_exists = false;
  std::optional<JournalManifest> manifest;
  std::string manifest_problem;  // why there is no manifest: empty when none was ever written
  std::int64_t block_files = 0;
  std::int64_t bytes = 0;        // on disk, blocks and manifest
};

class Journal {
 public:
  Journal(const std::string& output_path, std::string run_id);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  const std::string& directory() const { return directory_; }

  // Rank 0. Creates the directory (0700) when missing and locks it for this run: an open file
  // description lock, which the kernel releases however the process ends, so a killed run
  // never leaves a stale lock. Throws InputError naming the live holder when another run holds
  // it, or when the journal cannot be opened or trusted (a link, another user's directory, one
  // others can write to: io/owned_directory.hpp).
  void lock();

  // Rank 0, under the lock.
  JournalContents inspect() const;

  // Rank 0, under the lock: drops whatever an earlier run left and records `manifest`.
  void start(const JournalManifest& manifest);

  // Thread-safe, any rank: saves a finished block atomically, stamped with the run identity.
  // Throws std::runtime_error on I/O failure and leaves no temporary file behind.
  void save(const BlockResults& block) const;

  // Any rank, after save: makes the names of the blocks saved so far survive a power cut (a
  // block's own fsync covers its bytes, not its name). Throws std::runtime_error.
  void sync_saved() const;

  // Loads this run's saved block into `block` (range and column widths must match); false when
  // the block is missing, damaged or stamped by another run (then it is computed again).
  bool load(BlockResults& block) const;

  // Rank 0, under the lock, after the output is durably in place: removes the journal, the
  // lock last. Files the journal did not make stay (with a warning), and so does the directory.
  void remove();

 private:
  static std::string block_name(std::int64_t begin);
  // The directory, checked once: by lock() on rank 0, on first use on the other ranks.
  const OwnedDirectory& dir() const;
  void remove_blocks_then_manifest() const;
  std::string directory_;
  std::string run_id_;
  mutable std::once_flag opened_;
  mutable OwnedDirectory dir_;
  int lock_fd_ = -1;
  bool started_ = false;
};

}  // namespace cs
