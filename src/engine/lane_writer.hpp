// A lane's books (what travels with it from one tile to the other) and how its results are
// written into the block's columns: trajectory samples as they come, everything else when it
// finishes.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/mappers/basin_mapper.hpp"
#include "engine/run_plan.hpp"
#include "engine/settlement_records.hpp"
#include "engine/sync_tracker.hpp"
#include "numerics/lane_state.hpp"
#include "physics/energy_wells.hpp"
#include "physics/partials.hpp"

namespace cs {

template <int D>
struct LaneBook {
  std::int64_t point = -1;  // −1: empty slot
  std::int64_t n = 0;       // steps done
  bool non_finite = false;  // a trajectory sample written was not finite
  Settlement<2 * D> basin;  // where a basin mapper settled it
  std::int64_t samples_recorded = 0;  // trajectory samples 0 … samples_recorded − 1 written
  SyncTracker sync;
  double sync_omega[2] = {0.0, 0.0};  // the phases' ω of the sync's two dof, set at the lane's load
  std::int64_t sync_n = 0;  // an adaptive lane's next sync sample, a step of the nominal clock
  std::int64_t strobe_k = 0;  // an adaptive lane's next stroboscopic sample (RunPlan::attractors)
  std::int64_t window_n = 0;  // an adaptive lane's next observe_window sample, a nominal step
};

template <Scene S>
class LaneWriter {
  static constexpr int D = S::dof;
  static constexpr int N = 2 * D;
  static constexpr int kMaxVars = 2 * D + 2;  // q.., p.., z, lambda
  using Params = ParamsOf<S, double>;
  using Book = LaneBook<D>;

 public:
  LaneWriter(const RunPlan& plan, BlockResults& out)
      : plan_(plan),
        out_(out),
        records_(plan.map.basin_records >= 0 ? out.columns[static_cast<std::size_t>(plan.map.basin_records)]
                                             : unused_) {}

  void record_sample(Book& b, std::int64_t sample, const LaneState<D>& x, const Params& c) {
    double v[kMaxVars], H;
    state_values(x, c, v, H);
    const auto& map = plan_.map;
    bool finite = true;
    for (int k = 0; k < kMaxVars; ++k)
      if (map.traj_vars[k] >= 0) {
        column(map.traj_vars[k], b.point)[sample] = v[k];
        finite = finite && std::isfinite(v[k]);
      }
    if (map.traj_H >= 0) {
      column(map.traj_H, b.point)[sample] = H;
      finite = finite && std::isfinite(H);
    }
    if (!finite) b.non_finite = true;
  }

  // The recurrence mapper's record of the lane and why it is undecided (RunPlan::map).
  void finish_recurrence(std::int64_t point, const double* record, UndecidedReason why) {
    double* out = column(plan_.map.basin_cells, point);
    for (int k = 0; k < RecurrenceSearch::kRecordWidth; ++k) out[k] = record[k];
    column(plan_.map.undecided_reason, point)[0] = static_cast<double>(why);
  }

  // Writes a lane's results. A lane that ran (status ok) but wrote a value that is not finite
  // where the dataset promises one (ln λ or H overflowing, z where K is undefined along the
  // path) is flagged non_finite: its values are written as computed, its basin kept (decided on
  // q and p, which are finite), and no cell with a non-finite value reads ok. Cold: once per
  // lane (BlockRunner::load says why).
  [[gnu::cold]] void finish(const Book& b, const LaneState<D>& x, const Params& c, LaneStatus status,
              TrapVerdict verdict) {
    const auto& map = plan_.map;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto k = b.point;
    out_.lane_steps += b.n;
    double v[kMaxVars], H;
    state_values(x, c, v, H);
    if (status == LaneStatus::breakdown || status == LaneStatus::undefined_at_start) {
      for (auto& value : v) value = nan;
      H = nan;
    }
    bool finite = !b.non_finite;
    for (int i = 0; i < kMaxVars; ++i)
      if (map.final_vars[i] >= 0) {
        column(map.final_vars[i], k)[0] = v[i];
        finite = finite && std::isfinite(v[i]);
      }
    if (map.final_H >= 0) {
      column(map.final_H, k)[0] = H;
      finite = finite && std::isfinite(H);
    }
    if (map.sync_r >= 0) finite = finish_sync(b, status) && finite;
    if (map.basin >= 0) finish_basin(b, status);
    if (map.trap_verdict >= 0)
      out_.columns[static_cast<std::size_t>(map.trap_verdict)][static_cast<std::size_t>(verdict)] += 1.0;
    if (status == LaneStatus::ok && !finite) status = LaneStatus::non_finite;
    column(map.status, k)[0] = static_cast<double>(status);
    if (plan_.samples > 0) {
      // A failed lane's trajectory ends where it failed: every sample not recorded while it was
      // healthy is NaN, including one due at the look that found it failed (b.n). So does a
      // healthy lane's that ended before t_end (its basin settled with early stop, or a stop):
      // the samples it never reached were left at the columns' zeros, values a trajectory can
      // hold. A lane that ran to t_end recorded every sample: nothing to do.
      for (auto s = b.samples_recorded; s < plan_.samples; ++s) {
        for (int i = 0; i < kMaxVars; ++i)
          if (map.traj_vars[i] >= 0) column(map.traj_vars[i], k)[s] = nan;
        if (map.traj_H >= 0) column(map.traj_H, k)[s] = nan;
      }
    }
  }

 private:
  double* column(int c, std::int64_t point) {
    auto& col = out_.columns[static_cast<std::size_t>(c)];
    auto width = plan_.columns[static_cast<std::size_t>(c)].width;
    return col.data() + (point - out_.range.begin) * width;
  }

  void state_values(const LaneState<D>& x, const Params& c, double* v, double& H) const {
    for (int d = 0; d < D; ++d) v[d] = x.q[d], v[D + d] = x.p[d];
    v[2 * D] = x.z;
    const double log_lambda_now = log_lambda<S>(x);
    v[2 * D + 1] = log_lambda_now;
    // λK in the log domain: late in a damped run λ overflows while K underflows.
    double k = K<S>(x.q, x.p, x.z, c, x.t);
    H = k == 0.0 ? 0.0 : std::copysign(std::exp(log_lambda_now + std::log(std::fabs(k))), k);
  }

  // The label is provisional here (the number of the lane's settlement record, 0: none): the
  // attractor table, built once every block is done (attractor_table.hpp), labels the
  // attractors and relabels the lanes.
  void finish_basin(const Book& b, LaneStatus status) {
    const auto& map = plan_.map;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const bool ok = status == LaneStatus::ok && b.basin.settled;
    column(map.basin, b.point)[0] = ok ? records_.provisional_label(b.basin) : 0.0;
    column(map.settle_time, b.point)[0] = ok ? b.basin.settle_time : nan;
  }

  // False if a value it wrote is not finite where one exists (the frequency ratio of an
  // oscillator at rest, sync_amplitude = 0, does not).
  bool finish_sync(const Book& b, LaneStatus status) {
    const auto& map = plan_.map;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::int64_t n0 = plan_.sync_first_step, n1 = plan_.sync_last_step;
    SyncResult r{nan, nan, nan, nan};
    // An adaptive lane's b.n counts attempts: its window is complete when sync_n is past n1.
    if (status == LaneStatus::ok && (b.n >= n1 || b.sync_n > n1))
      r = b.sync.result(static_cast<double>(n1 - n0) * plan_.spec.h);
    column(map.sync_r, b.point)[0] = r.r;
    column(map.sync_phase_drift, b.point)[0] = r.phase_drift;
    column(map.sync_freq_ratio, b.point)[0] = r.freq_ratio;
    column(map.sync_amplitude, b.point)[0] = r.amplitude;
    if (!(status == LaneStatus::ok && b.n >= n1)) return true;  // nothing measured
    return std::isfinite(r.r) && std::isfinite(r.phase_drift) && std::isfinite(r.amplitude) &&
           (std::isfinite(r.freq_ratio) || r.amplitude == 0.0);
  }

  const RunPlan& plan_;
  BlockResults& out_;
  std::vector<double> unused_;  // records_' column where the run maps no basins
  SettlementRecords<N> records_;
};

}  // namespace cs
