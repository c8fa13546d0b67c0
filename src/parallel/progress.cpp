#include "parallel/progress.hpp"

#include <fmt/core.h>

namespace cs {

namespace {
constexpr double kReportInterval = 5.0;  // seconds between lines
}

ProgressReporter::ProgressReporter(std::int64_t local_points, std::int64_t total_points,
                                   std::int64_t steps, bool enabled)
    : local_points_(local_points), total_points_(total_points), steps_(steps), enabled_(enabled) {}

void ProgressReporter::add(std::int64_t points) {
  auto done = done_ += points;
  if (!enabled_ || local_points_ == 0) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  if (std::chrono::duration<double>(Clock::now() - last_).count() < kReportInterval) return;
  last_ = Clock::now();
  report(done);
}

void ProgressReporter::report(std::int64_t done) {
  double fraction = static_cast<double>(done) / static_cast<double>(local_points_);
  double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  double rate = fraction * static_cast<double>(total_points_) * static_cast<double>(steps_) / elapsed;
  double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  fmt::print(stderr, "contactsweep: {:5.1f}% done, {:.3g} traj-steps/s, ETA {:.0f} s\n",
             100.0 * fraction, rate, eta);
  std::fflush(stderr);
}

}  // namespace cs
