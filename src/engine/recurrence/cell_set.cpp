// CellSet's members compiled once, into the program; kernels of K call them here
// (engine/engine_export.hpp).
#include "engine/recurrence/cell_set.hpp"

namespace cs {

CellSet::Visit CellSet::visit(std::uint64_t key, bool locate) {
  if (!slots_.empty()) {
    std::uint64_t& slot = find(key);
    if (slot != kEmpty) {
      if (locate && !(slot & kLocated)) slot |= kLocated, ++located_;
      return Visit::seen;
    }
  }
  if (size_ >= max_cells_) return Visit::full;
  if (2 * (size_ + 1) > slots_.size()) grow();
  find(key) = key | (locate ? kLocated : 0);
  ++size_;
  located_ += locate;
  return Visit::added;
}

std::vector<std::uint64_t> CellSet::located_keys() const {
  std::vector<std::uint64_t> keys;
  keys.reserve(located_);
  for (std::uint64_t slot : slots_)
    if (slot != kEmpty && (slot & kLocated)) keys.push_back(slot & ~kLocated);
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::uint64_t CellSet::smallest_located() const {
  std::uint64_t best = kEmpty;
  for (std::uint64_t slot : slots_)
    if (slot != kEmpty && (slot & kLocated)) best = std::min(best, slot & ~kLocated);
  return best;
}

std::vector<std::uint64_t> CellSet::sketch(std::size_t k) const {
  std::vector<std::uint64_t> keys = located_keys();
  if (keys.size() > k) {
    std::nth_element(
        keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(k), keys.end(),
        [](std::uint64_t a, std::uint64_t b) { return cell_hash(a) < cell_hash(b); });
    keys.resize(k);
    std::sort(keys.begin(), keys.end());
  }
  return keys;
}

void CellSet::grow() {
  std::vector<std::uint64_t> old(std::max<std::size_t>(16, 2 * slots_.size()), kEmpty);
  old.swap(slots_);
  for (std::uint64_t slot : old)
    if (slot != kEmpty) find(slot & ~kLocated) = slot;
}

}  // namespace cs
