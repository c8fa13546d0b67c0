#include "parallel/progress.hpp"

#include "io/log.hpp"

namespace cs {

namespace {
constexpr double kReportInterval = 5.0;  // seconds between lines
}

ProgressReporter::ProgressReporter(std::int64_t local_points, std::int64_t total_points,
                                   std::int64_t steps, bool enabled)
    : local_points_(local_points), total_points_(total_points), steps_(steps), enabled_(enabled) {}

void ProgressReporter::add(std::int64_t points, bool computed) {
  auto done = done_ += points;
  auto integrated = computed ? computed_ += points : computed_.load();
  if (!enabled_ || local_points_ == 0) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  if (std::chrono::duration<double>(Clock::now() - last_).count() < kReportInterval) return;
  last_ = Clock::now();
  report(done, integrated);
}

void ProgressReporter::report(std::int64_t done, std::int64_t computed) {
  const double fraction = static_cast<double>(done) / static_cast<double>(local_points_);
  const double computed_fraction = static_cast<double>(computed) / static_cast<double>(local_points_);
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  const double rate =
      computed_fraction * static_cast<double>(total_points_) * static_cast<double>(steps_) / elapsed;
  // What is left goes at the pace of what was computed, not of blocks loaded from the journal.
  const double eta = computed_fraction > 0 ? elapsed * (1.0 - fraction) / computed_fraction : 0.0;
  log("contactsweep: {:5.1f}% done, {:.3g} traj-steps/s, ETA {:.0f} s", 100.0 * fraction, rate, eta);
}

}  // namespace cs
