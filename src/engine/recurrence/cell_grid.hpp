// The recurrence mapper's grid over phase space (Attractors.jl's `grid`, Datseris & Wagemakers
// 2022): a box cut into cells of equal size per variable, each cell named by one 64-bit key
// (mixed radix, the first variable varying fastest). An angle is folded into [0, period) first
// and its range is a whole number of cells, so q and q + 2π fall in the same cell. Keys stay
// below 2^53, so a key is also an exact double (the runner's columns hold doubles).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "engine/engine_export.hpp"

namespace cs {

// The number of cells along a variable: [lower, upper) cut into cells of `cell_size` (the last
// may reach past upper), or an angle's period cut into a whole number of cells of about that size.
inline double cells_along(double lower, double upper, double cell_size, double period) {
  if (period > 0.0) return std::fmax(1.0, std::nearbyint(period / cell_size));
  return std::ceil((upper - lower) / cell_size);
}

template <int N>
class CS_ENGINE_EXPORT CellGrid {
 public:
  static constexpr std::uint64_t kOutside = ~std::uint64_t{0};
  static constexpr double kMaxKeys = 9007199254740992.0;  // 2^53

  CellGrid() = default;

  // [lower, upper) per variable, cut into cells of about `cell_size` (angles: period > 0, their
  // range [0, period) cut into a whole number of cells; lower and upper are ignored). Throws
  // std::invalid_argument for a size that is not positive and finite, an empty box, or more
  // than 2^53 cells.
  CellGrid(const std::array<double, N>& lower, const std::array<double, N>& upper,
           const std::array<double, N>& cell_size, const std::array<double, N>& angle_period);

  // The cell of x, or kOutside (outside the box in a variable that is not an angle, or not
  // finite).
  std::uint64_t key(const double* x) const {
    std::uint64_t key = 0;
    for (int k = 0; k < N; ++k) {
      double u;
      if (period_[k] > 0.0) {
        const double folded = x[k] - period_[k] * std::floor(x[k] / period_[k]);
        // folded can round up to the period itself: that is the last cell.
        u = std::fmin(std::floor(folded / size_[k]), static_cast<double>(cells_[k] - 1));
        if (!(u >= 0.0)) return kOutside;  // NaN or ±∞
      } else {
        u = std::floor((x[k] - lower_[k]) / size_[k]);
        if (!(u >= 0.0 && u < static_cast<double>(cells_[k]))) return kOutside;
      }
      key += static_cast<std::uint64_t>(u) * stride_[k];
    }
    return key;
  }

  // The index of a key's cell along variable k.
  std::int64_t index(std::uint64_t key, int k) const {
    return static_cast<std::int64_t>((key / stride_[k]) % static_cast<std::uint64_t>(cells_[k]));
  }

  // The centre of a key's cell (angles in [0, period)).
  std::array<double, N> centre(std::uint64_t key) const {
    std::array<double, N> c{};
    for (int k = 0; k < N; ++k)
      c[k] = lower_[k] + (static_cast<double>(index(key, k)) + 0.5) * size_[k];
    return c;
  }

  // Whether two cells touch (share a face, an edge or a corner; angles wrap round).
  bool adjacent(std::uint64_t a, std::uint64_t b) const {
    for (int k = 0; k < N; ++k) {
      std::int64_t d = index(a, k) - index(b, k);
      if (d < 0) d = -d;
      if (period_[k] > 0.0) d = std::min(d, cells_[k] - d);
      if (d > 1) return false;
    }
    return true;
  }

  std::int64_t cells(int k) const { return cells_[k]; }
  double cell_size(int k) const { return size_[k]; }
  double lower(int k) const { return lower_[k]; }
  double angle_period(int k) const { return period_[k]; }

 private:
  std::array<double, N> lower_{}, size_{}, period_{};
  std::array<std::int64_t, N> cells_{};
  std::array<std::uint64_t, N> stride_{};
};

// Out of line, so that a kernel calls the program's copy (engine/engine_export.hpp).
template <int N>
CellGrid<N>::CellGrid(const std::array<double, N>& lower, const std::array<double, N>& upper,
                      const std::array<double, N>& cell_size,
                      const std::array<double, N>& angle_period) {
  double keys = 1.0;
  for (int k = 0; k < N; ++k) {
    if (!(cell_size[k] > 0.0) || !std::isfinite(cell_size[k]))
      throw std::invalid_argument("cell size of variable " + std::to_string(k) +
                                  " must be positive and finite");
    period_[k] = angle_period[k] > 0.0 ? angle_period[k] : 0.0;
    const double cells = cells_along(lower[k], upper[k], cell_size[k], period_[k]);
    if (period_[k] > 0.0) {
      lower_[k] = 0.0;
      size_[k] = period_[k] / cells;
    } else {
      if (!(upper[k] > lower[k]) || !std::isfinite(upper[k] - lower[k]))
        throw std::invalid_argument("empty box for variable " + std::to_string(k));
      lower_[k] = lower[k];
      size_[k] = cell_size[k];
    }
    keys *= cells;
    if (!(keys <= kMaxKeys))
      throw std::invalid_argument("more than 2^53 cells: make the cells larger");
    cells_[k] = static_cast<std::int64_t>(cells);
  }
  std::uint64_t stride = 1;
  for (int k = 0; k < N; ++k) {
    stride_[k] = stride;
    stride *= static_cast<std::uint64_t>(cells_[k]);
  }
}

extern template class CellGrid<2>;
extern template class CellGrid<4>;
extern template class CellGrid<6>;

}  // namespace cs
