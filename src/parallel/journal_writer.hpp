// Saves finished blocks to the journal from a thread of its own, so that the threads computing
// blocks never wait for the disk: a block is encoded, written, synced and renamed into place
// (journal.hpp) while the next one is computed. The syncs were the cost: on the 512² basin map
// (64 blocks, 0.3-5 ms per fsync here) they held the computing threads ~27 ms of a 0.47 s run.
//
// Durability is unchanged: a block counts as saved once its file is renamed into place, as
// before, and only then is it reported (on_saved). A kill loses the blocks still queued, as it
// loses the blocks still being computed; resume computes them again.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "engine/results.hpp"
#include "parallel/journal.hpp"

namespace cs {

class JournalWriter {
 public:
  static constexpr std::size_t kMaxQueued = 4;  // blocks waiting for their save
  // on_saved(n): on the writer's thread, after the n-th block of this writer is in place.
  // on_failure(): on the writer's thread, once, when a save fails; nothing is saved after it.
  // on_block_saved(block): on the writer's thread, before on_saved, with the block just saved
  // (the output stream takes it from there: parallel/block_stream.hpp).
  JournalWriter(const Journal& journal, std::function<void(std::int64_t)> on_saved,
                std::function<void()> on_failure,
                std::function<void(const BlockResults&)> on_block_saved = {});
  ~JournalWriter();  // waits for the queue like finish(), without throwing
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;

  // Thread-safe. `block` must stay alive and unchanged until finish() returns. Waits while
  // kMaxQueued blocks are queued: a slow disk slows the run down instead of letting finished
  // work pile up unsaved.
  void submit(const BlockResults& block);

  // Waits until every submitted block is saved (or dropped after a failure); rethrows the
  // first failure.
  void finish();

 private:
  void work();
  void close();

  const Journal& journal_;
  std::function<void(std::int64_t)> on_saved_;
  std::function<void()> on_failure_;
  std::function<void(const BlockResults&)> on_block_saved_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<const BlockResults*> queue_;
  bool closing_ = false;
  std::exception_ptr failure_;
  std::int64_t saved_ = 0;
  std::thread thread_;  // last: starts once everything it uses exists
};

}  // namespace cs
