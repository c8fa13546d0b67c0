// Where a block's settled lanes settled, kept compactly: each distinct (q.., p.., period) once,
// in the block's internal column RunPlan::map.basin_records (it grows as lanes settle), and in
// each settled lane's provisional `basin` value the number of its record plus one (0: not
// settled). The attractor table reads them back (attractor_table.cpp) and overwrites the
// provisional values with labels. Lanes of a map mostly settle on a few points, the same bits
// (the energy trap's minima, found once per parameter set): a (point, period) per lane cost the
// double well's 512² map 6 MB zeroed, written, checksummed and journalled.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "engine/engine_export.hpp"
#include "engine/mappers/basin_mapper.hpp"
#include "engine/results.hpp"
#include "engine/run_plan.hpp"
#include "engine/words_hash.hpp"

namespace cs {

template <int N>
class CS_ENGINE_EXPORT SettlementRecords {
  using Key = std::array<std::uint64_t, N + 1>;  // the bits of point.. and period
 public:
  explicit SettlementRecords(std::vector<double>& column) : column_(column) {}

  // The provisional `basin` value of a lane settled at s: its record's number plus one, the
  // record added if these bits are new to the block.
  double provisional_label(const Settlement<N>& s);

 private:
  std::vector<double>& column_;
  std::unordered_map<Key, double, WordsHash> numbers_;
  Key last_key_{};
  double last_ = 0.0;
};

// Out of line, so that a kernel calls the program's copy (engine/engine_export.hpp).
template <int N>
double SettlementRecords<N>::provisional_label(const Settlement<N>& s) {
  Key key;
  for (int k = 0; k < N; ++k) key[static_cast<std::size_t>(k)] = std::bit_cast<std::uint64_t>(s.point[static_cast<std::size_t>(k)]);
  key[N] = std::bit_cast<std::uint64_t>(static_cast<double>(s.period));
  if (last_ > 0.0 && key == last_key_) return last_;  // neighbours mostly share their point
  const auto [it, added] = numbers_.try_emplace(key, static_cast<double>(numbers_.size() + 1));
  if (added) {
    column_.insert(column_.end(), s.point.begin(), s.point.end());
    column_.push_back(static_cast<double>(s.period));
  }
  last_key_ = key;
  return last_ = it->second;
}

extern template class SettlementRecords<2>;
extern template class SettlementRecords<4>;
extern template class SettlementRecords<6>;

// A settled lane's (point.., period) from its provisional `basin` value, nullptr if it did not
// settle; `lane` counts from the block's first point. Valid until the block is labelled.
inline const double* settlement_of(const RunPlan& plan, const BlockResults& block, std::size_t lane) {
  const double provisional = block.columns[static_cast<std::size_t>(plan.map.basin)][lane];
  if (provisional == 0.0) return nullptr;
  const auto width = static_cast<std::size_t>(2 * plan.scene.dof + 1);
  const auto& records = block.columns[static_cast<std::size_t>(plan.map.basin_records)];
  const auto at = (static_cast<std::size_t>(provisional) - 1) * width;
  if (!(provisional >= 1.0) || at + width > records.size())  // never, short of a bug
    throw std::logic_error("a lane's basin record is missing from its block");
  return records.data() + at;
}

}  // namespace cs
