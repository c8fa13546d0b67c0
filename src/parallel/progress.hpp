// Progress reports on stderr from rank 0: percent done, trajectory-steps per second and ETA,
// one line at a time so that a batch log stays readable. Other ranks hold equal shares of the
// grid (round-robin blocks), so rank 0's share stands for the whole run.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>

namespace cs {

class ProgressReporter {
 public:
  ProgressReporter(std::int64_t local_points, std::int64_t total_points, std::int64_t steps,
                   bool enabled);
  // Thread-safe: called after each finished block; `computed` is false for a block a resume
  // loaded from the journal, which counts as done but not in the rate.
  void add(std::int64_t points, bool computed);

 private:
  void report(std::int64_t done, std::int64_t computed);
  using Clock = std::chrono::steady_clock;
  std::int64_t local_points_, total_points_, steps_;
  bool enabled_;
  std::atomic<std::int64_t> done_{0};
  std::atomic<std::int64_t> computed_{0};
  std::mutex mutex_;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

}  // namespace cs
