// Progress reports on stderr from rank 0: percent done, trajectory-steps per second and ETA,
// one line every 5 s so that a batch log stays readable. Other ranks hold equal shares of the
// grid (round-robin blocks), so rank 0's share stands for the whole run. Lines come from a
// thread of their own, whatever the blocks do: a run of a few lanes over 10^15 steps is one
// block, and its progress is counted inside it (the lane-steps its chunks integrate).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace cs {

class ProgressReporter {
 public:
  ProgressReporter(std::int64_t local_points, std::int64_t total_points, std::int64_t steps,
                   bool enabled);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  // Thread-safe: called after each finished block; `computed` is false for a block a resume
  // loaded from the journal, which counts as done but not in the rate.
  void add(std::int64_t points, bool computed);

  // Where running blocks count their lane-steps (BlockResults::in_flight_steps).
  std::atomic<std::int64_t>* in_flight_steps() { return &in_flight_steps_; }

  // This rank's share done, in [0, 1]: finished blocks plus the running blocks' lane-steps.
  double fraction() const;

 private:
  void report();
  using Clock = std::chrono::steady_clock;
  std::int64_t local_points_, total_points_, steps_;
  bool enabled_;
  std::atomic<std::int64_t> done_{0};
  std::atomic<std::int64_t> computed_{0};
  std::atomic<std::int64_t> in_flight_steps_{0};
  Clock::time_point start_ = Clock::now();
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

// A run watched from another thread (run_entry.cpp: the Python module's calling thread, which
// shows a bar and checks for Ctrl-C while the sweep computes). The sweep attaches its reporter
// while blocks run and starts no block once a stop is requested.
class RunControl {
 public:
  void request_stop() { stop_ = true; }
  bool stop_requested() const { return stop_.load(); }
  double fraction() const {
    const std::lock_guard lock(mutex_);
    return reporter_ ? reporter_->fraction() : finished_;
  }
  // For the lifetime of the sweep's loop; detaching keeps the last fraction.
  void attach(const ProgressReporter* reporter) {
    const std::lock_guard lock(mutex_);
    if (reporter_ != nullptr && reporter == nullptr) finished_ = reporter_->fraction();
    reporter_ = reporter;
  }

 private:
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  const ProgressReporter* reporter_ = nullptr;
  double finished_ = 0.0;
};

}  // namespace cs
