// How a run starts, given what an earlier run left at its output path: afresh, continuing its
// journal, or not at all because the output is complete — or refused, when the user must choose
// (--force, --resume). Rank 0 decides, under the journal's lock, and every rank follows: the
// file system may look different from other nodes (NFS attribute caches), and the decision
// must be one.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

#include "model/run_spec.hpp"
#include "parallel/journal.hpp"
#include "parallel/sweep.hpp"

namespace cs {

enum class Start : int { fresh, resume, complete };

struct StartDecision {
  Start start = Start::fresh;
  bool replace_output = false;     // the commit may replace an existing file (--force)
  bool remove_journal = false;     // complete: the journal is this run's, left by a kill
  std::int64_t journal_bytes = 0;  // already on disk, for the disk check
};

// Collective: rank 0 checks the output path, locks the journal (held until `journal` is
// destroyed or removed) and decides; every rank returns the same decision or throws the same
// InputError.
StartDecision agreed_start(const RunSpec& spec, const SweepOptions& options, Journal& journal,
                           const std::string& run_id, MPI_Comm comm);

}  // namespace cs
