// One lane's recurrence state machine (Attractors.jl's finite_state_machine.jl, Datseris &
// Wagemakers 2022, reduced to what one trajectory can decide alone). Samples of the lane's
// phase-space point (at looks, or on the stroboscopic map) are binned into CellGrid cells:
//   searching  a sample in a new cell resets the count of consecutive recurrences, a sample in a
//              visited cell adds one; `recurrences` in a row and the lane has found an attractor;
//   locating   the next `locate` samples flag their cells as the attractor's (located);
//   settled    the attractor is the located set, named by its smallest key.
// A lane that stays outside the box for more than `max_lost` samples in a row has left it; one
// with a coordinate that is not finite has diverged; one that would visit more than `max_cells`
// cells before settling gives up (too many cells: the cells are too small, or the orbit has not
// recurred). Samples outside the box neither count as recurrences nor reset the count (an
// attractor may graze the box's edge), as in Attractors.jl.
//
// Unlike Attractors.jl no lane sees the cells of another (its grid of labels is shared and grows
// as initial conditions are mapped, in their order): a lane's outcome depends on its own samples
// alone, so it is the same on any rank and thread. Attractors are told apart afterwards, by
// their located sets.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/recurrence/cell_grid.hpp"
#include "engine/recurrence/cell_set.hpp"

namespace cs {

enum class Recurrence : std::uint8_t {
  searching,
  locating,
  settled,
  left_box,
  diverged,
  too_many_cells,
};

inline bool finished(Recurrence r) {
  return r != Recurrence::searching && r != Recurrence::locating;
}

struct RecurrenceOptions {
  std::int64_t recurrences = 100;  // Attractors.jl's consecutive_recurrences
  std::int64_t locate = 1000;      // its attractor_locate_steps: samples that locate the cells
  std::int64_t max_lost = 20;      // its consecutive_lost_steps
  std::size_t max_cells = 16384;   // bounds a lane's memory: 16 B per cell at most
};

template <int N>
class RecurrenceTracker {
 public:
  void reset(std::size_t max_cells) {
    cells_.clear();
    cells_.set_max_cells(max_cells);
    state_ = Recurrence::searching;
    samples_ = consecutive_ = lost_ = last_new_ = located_samples_ = 0;
  }

  // Feeds the next sample x (q.., p..); returns the state after it. A finished lane ignores
  // further samples.
  Recurrence feed(const double* x, const CellGrid<N>& grid, const RecurrenceOptions& o) {
    if (finished(state_)) return state_;
    const std::int64_t k = samples_++;
    for (int j = 0; j < N; ++j)
      if (!std::isfinite(x[j])) return state_ = Recurrence::diverged;
    const std::uint64_t key = grid.key(x);
    if (state_ == Recurrence::locating) return locate(key, o);
    if (key == CellGrid<N>::kOutside) {
      if (++lost_ > o.max_lost) state_ = Recurrence::left_box;
      return state_;
    }
    lost_ = 0;
    switch (cells_.visit(key, false)) {
      case CellSet::Visit::full: return state_ = Recurrence::too_many_cells;
      case CellSet::Visit::added:
        consecutive_ = 0;
        last_new_ = k;
        return state_;
      case CellSet::Visit::seen:
        if (++consecutive_ >= o.recurrences) {
          state_ = Recurrence::locating;
          cells_.visit(key, true);  // this sample is the attractor's first
          located_samples_ = 1;
          if (located_samples_ >= o.locate) state_ = Recurrence::settled;
        }
        return state_;
    }
    return state_;
  }

  Recurrence state() const { return state_; }
  std::int64_t samples() const { return samples_; }
  // The sample that visited the last new cell before the recurrences: where the lane's settled
  // run began (its settle time, as the anchor test's).
  std::int64_t settle_sample() const { return last_new_; }
  std::size_t visited_cells() const { return cells_.size(); }
  std::size_t located_cells() const { return cells_.located(); }
  std::uint64_t representative() const { return cells_.smallest_located(); }
  std::vector<std::uint64_t> located_keys() const { return cells_.located_keys(); }
  std::vector<std::uint64_t> sketch(std::size_t k) const { return cells_.sketch(k); }

 private:
  Recurrence locate(std::uint64_t key, const RecurrenceOptions& o) {
    if (key != CellGrid<N>::kOutside && cells_.visit(key, true) == CellSet::Visit::full)
      return state_ = Recurrence::too_many_cells;
    if (++located_samples_ >= o.locate) state_ = Recurrence::settled;
    return state_;
  }

  CellSet cells_;
  Recurrence state_ = Recurrence::searching;
  std::int64_t samples_ = 0, consecutive_ = 0, lost_ = 0, last_new_ = 0, located_samples_ = 0;
};

}  // namespace cs
