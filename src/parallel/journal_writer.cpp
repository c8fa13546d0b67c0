#include "parallel/journal_writer.hpp"

#include <utility>

#include "parallel/team_cpus.hpp"

namespace cs {

JournalWriter::JournalWriter(const Journal& journal, std::function<void(std::int64_t)> on_saved,
                             std::function<void()> on_failure,
                             std::function<void(const BlockResults&)> on_block_saved)
    : journal_(journal),
      on_saved_(std::move(on_saved)),
      on_failure_(std::move(on_failure)),
      on_block_saved_(std::move(on_block_saved)),
      thread_([this] { work(); }) {}

JournalWriter::~JournalWriter() { close(); }

void JournalWriter::submit(const BlockResults& block) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < kMaxQueued || failure_; });
  if (failure_) return;  // the run is stopping; the failure is reported by finish()
  queue_.push_back(&block);
  changed_.notify_all();
}

void JournalWriter::finish() {
  close();
  if (failure_) std::rethrow_exception(failure_);
}

void JournalWriter::close() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void JournalWriter::work() {
  run_on_team_cpus();  // not on OpenMP thread 0's core alone (team_cpus.hpp)
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !queue_.empty() || closing_; });
    if (queue_.empty()) return;  // closing, and nothing left
    const BlockResults* block = queue_.front();
    lock.unlock();
    std::exception_ptr failed;
    try {
      journal_.save(*block);
      // One sync of the journal's names per drain of the queue, not per block: a writer that
      // falls behind catches up with fewer; one that keeps up syncs each, off the compute
      // threads. The last block of a run (or of a stop) always drains the queue.
      lock.lock();
      const bool drained = queue_.size() == 1;
      lock.unlock();
      if (drained) journal_.sync_saved();
    } catch (...) {
      failed = std::current_exception();
    }
    lock.lock();
    queue_.pop_front();
    if (failed) {
      failure_ = failed;
      queue_.clear();  // nothing is saved after a failure
    }
    changed_.notify_all();
    lock.unlock();
    if (failed) {
      on_failure_();
    } else {
      if (on_block_saved_) on_block_saved_(*block);
      on_saved_(++saved_);
    }
    lock.lock();
  }
}

}  // namespace cs
