#include "engine/wada_test.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace cs {
namespace {

using Mask = std::uint64_t;  // one bit per basin of the plane

// Chessboard distance to the nearest cell of `seed` (the two passes of Rosenfeld & Pfaltz's
// distance transform, exact for this metric), capped at kWadaMaxRadius + 1.
void chessboard_distance(const std::vector<char>& seed, std::int64_t rows, std::int64_t columns,
                         std::vector<std::uint8_t>& d) {
  constexpr std::uint8_t far = kWadaMaxRadius + 1;
  const auto at = [&](std::int64_t r, std::int64_t c) { return static_cast<std::size_t>(r * columns + c); };
  for (std::int64_t r = 0; r < rows; ++r)
    for (std::int64_t c = 0; c < columns; ++c) {
      std::uint8_t best = seed[at(r, c)] ? 0 : far;
      for (auto [dr, dc] : {std::pair{-1, -1}, {-1, 0}, {-1, 1}, {0, -1}})
        if (r + dr >= 0 && c + dc >= 0 && c + dc < columns)
          best = std::min<std::uint8_t>(best, std::min<std::uint8_t>(far, d[at(r + dr, c + dc)] + 1));
      d[at(r, c)] = best;
    }
  for (std::int64_t r = rows - 1; r >= 0; --r)
    for (std::int64_t c = columns - 1; c >= 0; --c) {
      std::uint8_t best = d[at(r, c)];
      for (auto [dr, dc] : {std::pair{1, 1}, {1, 0}, {1, -1}, {0, 1}})
        if (r + dr < rows && c + dc >= 0 && c + dc < columns)
          best = std::min<std::uint8_t>(best, std::min<std::uint8_t>(far, d[at(r + dr, c + dc)] + 1));
      d[at(r, c)] = best;
    }
}

}  // namespace

namespace wada_detail {

// The plane's labels met in order (a map has few: a linear search per cell, and the one met
// last first).
void collect_basins(const std::int32_t* labels, std::size_t cells, std::vector<std::int32_t>& basins) {
  std::int32_t last = 0;
  for (std::size_t i = 0; i < cells; ++i) {
    if (labels[i] == 0 || labels[i] == last) continue;
    last = labels[i];
    if (basins.size() > static_cast<std::size_t>(kWadaMaxBasins)) return;
    if (std::find(basins.begin(), basins.end(), last) == basins.end()) basins.push_back(last);
  }
}

void count_rows(const std::int32_t* band, std::int64_t band_first, std::int64_t rows,
                std::int64_t columns, std::int64_t first, std::int64_t end,
                const std::vector<std::int32_t>& basins, WadaTest& out) {
  // The seeds that can lie within kWadaMaxRadius of [first, end): the capped distance of a cell
  // there is the same over these rows as over the whole plane.
  const std::int64_t seed_first = std::max<std::int64_t>(first - kWadaMaxRadius - 1, 0);
  const std::int64_t seed_end = std::min<std::int64_t>(end + kWadaMaxRadius + 1, rows);
  const std::int64_t seed_rows = seed_end - seed_first;
  const auto cells = static_cast<std::size_t>(seed_rows * columns);
  const auto label = [&](std::int64_t r, std::int64_t c) {
    return band[static_cast<std::size_t>((r - band_first) * columns + c)];
  };
  const auto bit = [&](std::int32_t l) {
    return Mask{1} << (std::lower_bound(basins.begin(), basins.end(), l) - basins.begin());
  };
  const Mask all = basins.size() == 64 ? ~Mask{0} : (Mask{1} << basins.size()) - 1;
  // Each decided cell's own basin and the basins in its 3 × 3 neighbourhood.
  std::vector<Mask> own(cells, 0), near(cells, 0);
  for (std::int64_t r = seed_first; r < seed_end; ++r)
    for (std::int64_t c = 0; c < columns; ++c) {
      const auto i = static_cast<std::size_t>((r - seed_first) * columns + c);
      if (label(r, c) == 0) continue;
      own[i] = bit(label(r, c));
      for (std::int64_t rr = std::max<std::int64_t>(r - 1, 0); rr <= std::min(r + 1, rows - 1); ++rr)
        for (std::int64_t cc = std::max<std::int64_t>(c - 1, 0); cc <= std::min(c + 1, columns - 1); ++cc) {
          const std::int32_t l = label(rr, cc);
          if (l != 0) near[i] |= bit(l);
        }
    }
  // How far each boundary cell is from the boundary of each merged map (basin j against the
  // rest): the largest of those distances.
  std::vector<std::uint8_t> farthest(cells, 0), d(cells);
  std::vector<char> seed(cells);
  for (std::size_t j = 0; j < basins.size(); ++j) {
    const Mask b = Mask{1} << j;
    for (std::size_t i = 0; i < cells; ++i)
      seed[i] = own[i] != 0 && ((own[i] == b) ? (near[i] & ~b) != 0 : (near[i] & b) != 0);
    chessboard_distance(seed, seed_rows, columns, d);
    for (std::size_t i = 0; i < cells; ++i) farthest[i] = std::max(farthest[i], d[i]);
  }
  out.covered.resize(kWadaMaxRadius, 0);
  const auto from = static_cast<std::size_t>((first - seed_first) * columns);
  const auto to = static_cast<std::size_t>((end - seed_first) * columns);
  for (std::size_t i = from; i < to; ++i) {
    if (std::popcount(near[i]) < 2) continue;  // not on a boundary
    ++out.boundary_cells;
    out.touching_all += near[i] == all;
    for (int r = farthest[i]; r >= 1 && r <= kWadaMaxRadius; ++r) ++out.covered[static_cast<std::size_t>(r - 1)];
    if (farthest[i] == 0)
      for (auto& n : out.covered) ++n;
  }
}

}  // namespace wada_detail

double WadaTest::touching_fraction() const {
  return applies() ? static_cast<double>(touching_all) / static_cast<double>(boundary_cells)
                   : std::numeric_limits<double>::quiet_NaN();
}

double WadaTest::covered_fraction(int radius) const {
  return applies() ? static_cast<double>(covered[static_cast<std::size_t>(radius - 1)]) /
                         static_cast<double>(boundary_cells)
                   : std::numeric_limits<double>::quiet_NaN();
}

bool WadaTest::wada() const {
  return applies() && covered_fraction(kWadaVerdictRadius) >= kWadaVerdictFraction;
}

std::string WadaTest::verdict() const {
  if (!applies()) {
    if (planes_too_many > 0)
      return fmt::format("not tested: more than {} basins in a plane", kWadaMaxBasins);
    return "not tested: it needs a 2-D plane of initial conditions with three basins or more";
  }
  return fmt::format(
      "{}: {:.4f} of the {} boundary cells lie within {} cells of every merged basin's "
      "boundary (merging method; Wada from {:.2f}); {:.4f} touch every basin in their 3 x 3 "
      "neighbourhood",
      wada() ? "Wada" : "not Wada", covered_fraction(kWadaVerdictRadius), boundary_cells,
      kWadaVerdictRadius, kWadaVerdictFraction, touching_fraction());
}

}  // namespace cs
