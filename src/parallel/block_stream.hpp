// Finished blocks go to the output file while the run goes on, so that no rank holds the whole
// map: rank 0 writes its own blocks as they are saved in the journal and receives the
// other ranks' as they finish theirs; a block's streamed columns are freed once written or sent.
// A rank then holds its blocks in flight (computing, queued for the journal, queued here) and
// the columns that are written only at the end (`basin`, whose labels need every block, and the
// internal columns the basin summary reads).
//
// One writer still (output_assembly.hpp says why): rank 0 alone calls HDF5, no HDF5 call spans
// ranks, and a failed write on rank 0 is reported to the failure watch and agreed afterwards
// while rank 0 keeps receiving, so no sender waits. MPI is initialised FUNNELED: every MPI call
// here is made on the main thread (poll, finish); add() only queues.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "engine/results.hpp"
#include "engine/run_plan.hpp"
#include "io/output_file.hpp"

namespace cs {

// Writes one column's values over `ranges` (sorted, disjoint), converted to the dataset's type.
void write_values(OutputFile& file, const DatasetSpec& dataset,
                  const std::vector<PointRange>& ranges, const std::vector<double>& values);

class BlockStream {
 public:
  struct Column {
    int index;            // in the plan's columns
    std::int64_t width;   // values per point
    DatasetSpec dataset;  // as written
  };
  // `file`: rank 0's output (its datasets created), nullptr on the other ranks. `on_failure`:
  // rank 0, once, when a write fails (the caller stops the run; the failure is kept, failure()).
  // Collective (duplicates `comm`: its messages never match another exchange's).
  BlockStream(std::vector<Column> columns, OutputFile* file, std::function<void()> on_failure,
              MPI_Comm comm);
  ~BlockStream();
  BlockStream(const BlockStream&) = delete;
  BlockStream& operator=(const BlockStream&) = delete;

  // Thread-safe: `block` is saved in the journal (or was loaded from it) and nothing else reads
  // its streamed columns any more. It must stay alive until finish(); its other columns are kept.
  void add(BlockResults& block);

  // Main thread, between blocks: rank 0 writes what is queued and what has arrived; the other
  // ranks start sending what is queued and free what has gone.
  void poll();

  // Main thread, after this rank's last block (or a failure): everything queued goes out; rank 0
  // then receives until every rank has said it is done, calling `idle` while it waits (the
  // failure watch's rounds).
  void finish(const std::function<void()>& idle);

  // Rank 0: the first failed write, or nullptr.
  std::exception_ptr failure() const { return failure_; }

 private:
  struct Sending;
  void write(PointRange range, const std::vector<const std::vector<double>*>& values);
  void write_own(BlockResults& block);
  void start_send(BlockResults& block);
  void complete_sends(bool wait);
  bool receive_one();  // rank 0: false when no message is waiting
  static void release(BlockResults& block, const std::vector<Column>& columns);

  std::vector<Column> columns_;
  OutputFile* file_;
  std::function<void()> on_failure_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, ranks_ = 1, done_ranks_ = 0;
  std::mutex mutex_;
  std::deque<BlockResults*> queued_;
  std::deque<std::unique_ptr<Sending>> sending_;
  std::exception_ptr failure_;
};

}  // namespace cs
