// The Wada test of a basin map: do three or more basins share one boundary? Two measures of each
// 2-D plane of labels (8-neighbour cells, undecided cells left out):
// - the grid method's first level (Daza, Wagemakers, Sanjuán, Sci. Rep. 5, 16579, 2015): the
//   fraction of boundary cells whose 3 × 3 neighbourhood holds every basin of the plane;
// - the merging method (Daza, Wagemakers, Sanjuán, Sci. Rep. 8, 9954, 2018): merge every basin
//   but one into a single one; a Wada boundary is the only boundary that stays the same under
//   every such merging. Measured here as how far each boundary cell lies from the boundary of
//   each merged map (chessboard distance, in cells): a Wada boundary lies within a few cells of
//   every one of them, while a boundary of sectors meeting at a point drifts away from them
//   along its length.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cs {

struct WadaTest {
  // Cells on a boundary of planes with three basins or more (0: the test does not apply).
  std::int64_t boundary_cells = 0;
  std::int64_t touching_all = 0;  // … whose 3 × 3 neighbourhood holds every basin
  // covered[r − 1]: … within r cells of every merged map's boundary, r = 1 … kWadaMaxRadius.
  std::vector<std::int64_t> covered;
  int planes_tested = 0;     // planes with three basins or more
  int planes_too_many = 0;   // planes with more basins than the test follows (kWadaMaxBasins)

  double touching_fraction() const;
  double covered_fraction(int radius) const;
  bool applies() const { return boundary_cells > 0; }
  bool wada() const;  // the verdict: covered_fraction(kWadaVerdictRadius) >= kWadaVerdictFraction
  std::string verdict() const;  // for the file's `wada` attribute and the log
};

inline constexpr int kWadaMaxRadius = 8;
inline constexpr int kWadaMaxBasins = 64;
// A boundary is called Wada when nearly all of its cells lie within this many cells of the
// boundary of every merged map (tests/test_wada.cpp: Newton's basins of z³ = 1, proved Wada, are
// called Wada from 128² cells on; sectors meeting at a point are not, at any resolution).
inline constexpr int kWadaVerdictRadius = 3;
inline constexpr double kWadaVerdictFraction = 0.95;

// The test's parts, for a plane read a band of rows at a time (engine/strip_statistics.hpp runs
// it on every 2-D plane of a map, 0 standing for undecided cells).
namespace wada_detail {
// Rows of labels a band needs on each side of the rows it counts: kWadaMaxRadius for the capped
// distance, one for the seeds' neighbourhood, one for theirs.
inline constexpr std::int64_t kHalo = kWadaMaxRadius + 2;
// Adds the plane's labels met, but 0, to `basins` (unsorted; it stops one past kWadaMaxBasins).
void collect_basins(const std::int32_t* labels, std::size_t cells, std::vector<std::int32_t>& basins);
// Adds to `out` the counts of rows [first, end) of a plane of rows × columns cells whose basins
// are `basins` (sorted, 3 to kWadaMaxBasins). `band` holds rows [band_first, …) of the plane,
// at least [first − kHalo, end + kHalo) within it. Integer counts: the sum over bands is the
// whole plane's, whatever the cut.
void count_rows(const std::int32_t* band, std::int64_t band_first, std::int64_t rows,
                std::int64_t columns, std::int64_t first, std::int64_t end,
                const std::vector<std::int32_t>& basins, WadaTest& out);
}  // namespace wada_detail

}  // namespace cs
