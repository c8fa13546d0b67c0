#include "parallel/progress.hpp"

#include <algorithm>
#include <cstdlib>

#include "io/log.hpp"

namespace cs {

namespace {

// Between lines: 5 s, or CONTACTSWEEP_PROGRESS_SECONDS (a batch log may want fewer lines).
std::chrono::duration<double> report_interval() {
  if (const char* text = std::getenv("CONTACTSWEEP_PROGRESS_SECONDS")) {
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (end != text && *end == '\0' && seconds >= 0.01 && seconds <= 1e6)
      return std::chrono::duration<double>(seconds);
  }
  return std::chrono::duration<double>(5.0);
}

}  // namespace

ProgressReporter::ProgressReporter(std::int64_t local_points, std::int64_t total_points,
                                   std::int64_t steps, bool enabled)
    : local_points_(local_points), total_points_(total_points), steps_(steps), enabled_(enabled) {
  if (!enabled_ || local_points_ == 0) return;
  thread_ = std::thread([this, interval = report_interval()] {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, interval, [this] { return stop_; })) report();
  });
}

ProgressReporter::~ProgressReporter() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void ProgressReporter::add(std::int64_t points, bool computed) {
  done_ += points;
  if (computed) computed_ += points;
}

double ProgressReporter::fraction() const {
  if (local_points_ == 0) return 1.0;
  // Points of finished blocks, plus the running blocks' lane-steps as a share of a point's.
  const double running = static_cast<double>(std::max<std::int64_t>(in_flight_steps_.load(), 0)) /
                         static_cast<double>(std::max<std::int64_t>(steps_, 1));
  return std::min(1.0, (static_cast<double>(done_.load()) + running) /
                           static_cast<double>(local_points_));
}

void ProgressReporter::report() {
  const double running = static_cast<double>(std::max<std::int64_t>(in_flight_steps_.load(), 0)) /
                         static_cast<double>(std::max<std::int64_t>(steps_, 1));
  const double local = static_cast<double>(local_points_);
  const double fraction = this->fraction();
  const double computed_fraction =
      std::min(1.0, (static_cast<double>(computed_.load()) + running) / local);
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  const double rate =
      computed_fraction * static_cast<double>(total_points_) * static_cast<double>(steps_) / elapsed;
  // What is left goes at the pace of what was computed, not of blocks loaded from the journal.
  const double eta = computed_fraction > 0 ? elapsed * (1.0 - fraction) / computed_fraction : 0.0;
  log("contactsweep: {:5.1f}% done, {:.3g} traj-steps/s, ETA {:.0f} s", 100.0 * fraction, rate, eta);
}

}  // namespace cs
