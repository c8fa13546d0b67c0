// The hash of a record kept once per distinct value: an array of 64-bit words (the bits of its
// doubles), each mixed in with the multiplier of MurmurHash3's finaliser. One function for the
// block's settlements (settlement_records.hpp) and a saved block's recurrence records
// (recurrence/lane_records.cpp), whose keys are such arrays.
#pragma once

#include <cstddef>
#include <cstdint>

namespace cs {

struct WordsHash {
  template <class Words>
  std::size_t operator()(const Words& words) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (std::uint64_t v : words) h = (h ^ v) * 0xff51afd7ed558ccdULL, h ^= h >> 32;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace cs
