// Basin maps held in memory for the tests of their statistics (test_strip_statistics.cpp,
// test_wada.cpp): a reader over the array, the statistics of a map with the program's bands,
// and maps whose answer is known.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <numbers>
#include <vector>

#include "engine/strip_statistics.hpp"

namespace cs::test {

// Reads `labels`; the longest read so far into *largest_read, and the cells read in all into
// *total_read, if given.
inline LabelReader reader_of(const std::vector<BasinLabel>& labels, std::int64_t* largest_read = nullptr,
                             std::int64_t* total_read = nullptr) {
  return [&labels, largest_read, total_read](std::int64_t begin, std::int64_t end, BasinLabel* out) {
    ASSERT_LE(0, begin);
    ASSERT_LE(begin, end);
    ASSERT_LE(end, static_cast<std::int64_t>(labels.size()));
    std::memcpy(out, labels.data() + begin, static_cast<std::size_t>(end - begin) * sizeof(BasinLabel));
    if (largest_read) *largest_read = std::max(*largest_read, end - begin);
    if (total_read) *total_read += end - begin;
  };
}

inline BasinStatistics statistics_of(const std::vector<BasinLabel>& labels, const BasinMapShape& shape) {
  return strip_statistics(shape, reader_of(labels)).whole;
}

// The Wada test of `planes` planes of n × n cells, one after the other.
inline WadaTest wada_of(const std::vector<BasinLabel>& labels, std::int64_t planes, std::int64_t n) {
  return statistics_of(labels, {{planes, n, n}, 2}).wada;
}

// Basins of Newton's method for z³ = 1 over [−2, 2]², cell centres; 0 where it has not converged.
inline std::vector<BasinLabel> newton_basins(int n) {
  std::vector<BasinLabel> labels(static_cast<std::size_t>(n) * n, 0);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      std::complex<double> z(-2.0 + 4.0 * (c + 0.5) / n, -2.0 + 4.0 * (r + 0.5) / n);
      for (int k = 0; k < 200; ++k) {
        z -= (z * z * z - 1.0) / (3.0 * z * z);
        for (int j = 0; j < 3; ++j)
          if (std::abs(z - std::polar(1.0, 2.0 * std::numbers::pi * j / 3.0)) < 1e-9) {
            labels[static_cast<std::size_t>(r) * n + c] = j + 1;
            k = 200;
          }
      }
    }
  return labels;
}

// Three sectors of 120° around the centre of [−1, 1]².
inline std::vector<BasinLabel> sectors(int n) {
  std::vector<BasinLabel> labels(static_cast<std::size_t>(n) * n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double angle = std::atan2(-1.0 + 2.0 * (r + 0.5) / n, -1.0 + 2.0 * (c + 0.5) / n) + std::numbers::pi;
      labels[static_cast<std::size_t>(r) * n + c] = 1 + static_cast<int>(angle / (2.0 * std::numbers::pi / 3.0)) % 3;
    }
  return labels;
}

}  // namespace cs::test
