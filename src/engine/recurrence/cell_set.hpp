// One lane's visited cells: a small open-addressing hash set of cell keys (CellGrid keys, below
// 2^53) with linear probing, a power-of-two table kept at most half full, grown by doubling and
// bounded: it holds at most `max_cells` keys, and refuses the next one. Each key carries one
// flag, "located" (a cell of the attractor, seen after the recurrences), in its top bit. The
// table is kept when the set is cleared, so a slot reused by lane after lane stops allocating.
// Its members that are not inline are compiled once, into the program (cell_set.cpp), and a
// kernel of K calls them there (docs/performance.md, "First build of a new K").
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/engine_export.hpp"

namespace cs {

// splitmix64's finaliser: neighbouring cells (keys differing in low bits or by a stride) land
// far apart in the table, and a set's keys of smallest hash are a fair sample of it (sketch()).
inline std::uint64_t cell_hash(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class CS_ENGINE_EXPORT CellSet {
 public:
  enum class Visit : std::uint8_t { seen, added, full };

  explicit CellSet(std::size_t max_cells = 0) : max_cells_(max_cells) {}

  void set_max_cells(std::size_t max_cells) { max_cells_ = max_cells; }
  std::size_t size() const { return size_; }
  std::size_t located() const { return located_; }
  std::size_t capacity() const { return slots_.size(); }

  void clear() {
    if (size_ != 0) std::fill(slots_.begin(), slots_.end(), kEmpty);
    size_ = located_ = 0;
  }

  // Adds `key` unless it is there (seen) or the set is full; with `locate`, flags it located.
  Visit visit(std::uint64_t key, bool locate);

  bool contains(std::uint64_t key) const {
    if (slots_.empty()) return false;
    return const_cast<CellSet*>(this)->find(key) != kEmpty;
  }

  // The located keys, in increasing order.
  std::vector<std::uint64_t> located_keys() const;

  // The smallest located key (kEmpty if none): a located set's canonical name.
  std::uint64_t smallest_located() const;

  // At most k located keys, those of smallest cell_hash, in increasing order of key: a bottom-k
  // sketch. Two lanes that located the same cells have the same sketch; two that located large
  // parts of one chaotic attractor share keys with a probability that grows with the overlap.
  std::vector<std::uint64_t> sketch(std::size_t k) const;

  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

 private:
  static constexpr std::uint64_t kLocated = std::uint64_t{1} << 63;

  // The slot holding key, or the empty slot where it would go (the table is never full).
  std::uint64_t& find(std::uint64_t key) {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = cell_hash(key) & mask;; i = (i + 1) & mask)
      if (slots_[i] == kEmpty || (slots_[i] & ~kLocated) == key) return slots_[i];
  }

  void grow();

  std::vector<std::uint64_t> slots_;
  std::size_t size_ = 0, located_ = 0, max_cells_;
};

}  // namespace cs
