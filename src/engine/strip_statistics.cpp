#include "engine/strip_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numeric>
#include <utility>

#include "engine/wada_test.hpp"

namespace cs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::int64_t kBox = kBasinEntropyBoxCells;  // cells along each axis of a box

// The labels met in one box and how often: a few pairs, searched linearly (a std::map per box
// cost ~10 ms on a 512² map).
struct BoxCounts {
  std::vector<std::pair<int, int>> counts;
  void add(int label) {
    for (auto& [l, n] : counts)
      if (l == label) {
        ++n;
        return;
      }
    counts.emplace_back(label, 1);
  }
  double entropy(int total) const {
    double s = 0.0;
    for (const auto& [label, n] : counts) {
      const double p = static_cast<double>(n) / total;
      s -= p * std::log(p);
    }
    return s;
  }
};

// Least-squares slope of log f against log ε over the points with f > 0 (NaN under 3).
double log_log_slope(const std::vector<int>& eps, const std::vector<double>& f) {
  std::vector<double> x, y;
  for (std::size_t k = 0; k < eps.size(); ++k)
    if (f[k] > 0.0) x.push_back(std::log(eps[k])), y.push_back(std::log(f[k]));
  if (x.size() < 3) return kNaN;
  const double n = static_cast<double>(x.size());
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n;
  const double my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
    sxy += (x[k] - mx) * (y[k] - my), sxx += (x[k] - mx) * (x[k] - mx);
  return sxy / sxx;
}

// Cells per label, in an array from the lowest label met (labels are few and close together:
// -1, the double well's left well, to the number of attractors).
class LabelCounts {
 public:
  void add(BasinLabel label, std::int64_t n = 1) {
    if (counts_.empty()) lowest_ = label;
    if (label < lowest_) {
      counts_.insert(counts_.begin(), static_cast<std::size_t>(std::int64_t{lowest_} - label), 0);
      lowest_ = label;
    }
    const auto k = static_cast<std::size_t>(std::int64_t{label} - lowest_);
    if (k >= counts_.size()) counts_.resize(k + 1, 0);
    counts_[k] += n;
  }
  template <class F>
  void each(F f) const {
    for (std::size_t k = 0; k < counts_.size(); ++k)
      if (counts_[k] > 0) f(static_cast<int>(lowest_ + static_cast<BasinLabel>(k)), counts_[k]);
  }

 private:
  BasinLabel lowest_ = 0;
  std::vector<std::int64_t> counts_;
};

// One map's statistics as its bands come (the whole map, or one slice of it).
struct Tally {
  LabelCounts cells;
  std::int64_t points = 0;
  double sum = 0.0, boundary_sum = 0.0;  // entropies, added box by box in order
  std::int64_t boxes = 0, boundary_boxes = 0;
  std::vector<std::int64_t> eps_cells, eps_uncertain;
  WadaTest wada;
};

BasinStatistics finish(const Tally& t, int plane_axes, const std::vector<int>& eps) {
  BasinStatistics out;
  out.points = t.points;
  t.cells.each([&](int label, std::int64_t n) { out.cells[label] = n; });
  if (plane_axes == 0) {
    out.basin_entropy = out.boundary_basin_entropy = kNaN;
    out.uncertainty_exponent = out.boundary_dimension = kNaN;
    return out;
  }
  out.boxes = t.boxes;
  out.boundary_boxes = t.boundary_boxes;
  out.basin_entropy = t.boxes > 0 ? t.sum / static_cast<double>(t.boxes) : kNaN;
  out.boundary_basin_entropy =
      t.boundary_boxes > 0 ? t.boundary_sum / static_cast<double>(t.boundary_boxes) : kNaN;
  out.epsilon_cells = eps;
  for (std::size_t k = 0; k < eps.size(); ++k)
    out.uncertain_fraction.push_back(
        t.eps_cells[k] > 0
            ? static_cast<double>(t.eps_uncertain[k]) / static_cast<double>(t.eps_cells[k])
            : kNaN);
  out.uncertainty_exponent = log_log_slope(out.epsilon_cells, out.uncertain_fraction);
  out.boundary_dimension = plane_axes - out.uncertainty_exponent;
  out.wada = t.wada;
  return out;
}

void add_wada(WadaTest& to, const WadaTest& from) {
  to.boundary_cells += from.boundary_cells;
  to.touching_all += from.touching_all;
  if (!from.covered.empty()) to.covered.resize(kWadaMaxRadius, 0);
  for (std::size_t r = 0; r < from.covered.size(); ++r) to.covered[r] += from.covered[r];
  to.planes_tested += from.planes_tested;
  to.planes_too_many += from.planes_too_many;
}

class StripPass {
 public:
  StripPass(const BasinMapShape& shape, const LabelReader& read, const StripOptions& options)
      : shape_(shape), read_(read), options_(options) {
    const auto n = shape.dims.size();
    const auto first_plane_axis = n - static_cast<std::size_t>(shape.plane_axes);
    for (std::size_t a = 0; a < first_plane_axis; ++a) slices_ *= shape.dims[a];
    if (shape.plane_axes >= 1) columns_ = shape.dims[n - 1];
    if (shape.plane_axes == 2) rows_ = shape.dims[n - 2];
    if (shape.plane_axes > 0) {
      const std::int64_t side = shape.plane_axes == 2 ? std::min(rows_, columns_) : columns_;
      for (std::int64_t e = 1; 8 * e <= side; e *= 2) eps_.push_back(static_cast<int>(e));
    }
    strip_ = options.strip_rows > 0 ? options.strip_rows
                                    : std::max<std::int64_t>(1, kStripCells / std::max<std::int64_t>(columns_, 1));
    segment_ = options.line_cells > 0 ? options.line_cells : kStripCells;
    if (options.fractions_axis >= 0) {
      stride_ = 1;
      for (std::size_t a = static_cast<std::size_t>(options.fractions_axis) + 1; a < n; ++a)
        stride_ *= shape.dims[a];
      values_ = shape.dims[static_cast<std::size_t>(options.fractions_axis)];
      along_.resize(static_cast<std::size_t>(values_));
    }
    if (options.per_slice) per_slice_.resize(static_cast<std::size_t>(slices_));
    whole_.eps_cells.assign(eps_.size(), 0);
    whole_.eps_uncertain.assign(eps_.size(), 0);
    for (Tally& t : per_slice_) t.eps_cells = t.eps_uncertain = whole_.eps_cells;
  }

  MapStatistics run() {
    if (shape_.plane_axes == 0) {
      count_flat();
    } else if (shape_.plane_axes == 1) {
      for (std::int64_t s = 0; s < slices_; ++s) line(s);
    } else {
      for (std::int64_t s = 0; s < slices_; ++s) slice(s);
    }
    MapStatistics out;
    out.most_cells_held = most_held_;
    out.whole = finish(whole_, shape_.plane_axes, eps_);
    for (const Tally& t : per_slice_) out.per_slice.push_back(finish(t, shape_.plane_axes, eps_));
    for (std::size_t v = 0; v < along_.size(); ++v) {
      std::map<int, double> f;
      std::int64_t total = 0;
      along_[v].each([&](int label, std::int64_t n) { f[label] = static_cast<double>(n), total += n; });
      for (auto& [label, x] : f) x /= static_cast<double>(total);  // sums of 1.0: exact counts
      out.fractions.push_back(std::move(f));
    }
    return out;
  }

 private:
  std::int64_t flat(std::int64_t slice, std::int64_t row) const { return (slice * rows_ + row) * columns_; }

  // Rows [first, end) of a slice, into `band`.
  void read_rows(std::int64_t slice, std::int64_t first, std::int64_t end, std::vector<BasinLabel>& band) {
    fit(band, (end - first) * columns_);
    if (end > first) read_(flat(slice, first), flat(slice, end), band.data());
  }

  // `cells` resized to n, its capacity n when it grows: a vector grown by resize() may double
  // its capacity, and the memory check counts each buffer at the most it is asked to hold
  // (summary_bytes_on_rank0). The old contents are not kept: every caller reads over them.
  static void fit(std::vector<BasinLabel>& cells, std::int64_t n) {
    if (static_cast<std::size_t>(n) > cells.capacity()) std::vector<BasinLabel>().swap(cells);
    cells.resize(static_cast<std::size_t>(n));
  }

  // The labels the buffers hold at once, as their capacities (MapStatistics::most_cells_held).
  void note_held(std::initializer_list<const std::vector<BasinLabel>*> buffers) {
    std::size_t cells = 0;
    for (const auto* b : buffers) cells += b->capacity();
    most_held_ = std::max(most_held_, static_cast<std::int64_t>(cells));
  }

  void count_cells(const BasinLabel* labels, std::int64_t begin, std::int64_t end, Tally* slice) {
    for (std::int64_t i = begin; i < end; ++i) {
      const BasinLabel l = labels[i - begin];
      whole_.cells.add(l);
      if (slice) slice->cells.add(l);
      if (values_ > 0) along_[static_cast<std::size_t>((i / stride_) % values_)].add(l);
    }
    whole_.points += end - begin;
    if (slice) slice->points += end - begin;
  }

  void count_flat() {
    const std::int64_t points = slices_;
    std::vector<BasinLabel> chunk;
    for (std::int64_t begin = 0; begin < points; begin += kStripCells) {
      const std::int64_t end = std::min(points, begin + kStripCells);
      fit(chunk, end - begin);
      note_held({&chunk});
      read_(begin, end, chunk.data());
      count_cells(chunk.data(), begin, end, per_slice_.empty() ? nullptr : &per_slice_[0]);
    }
  }

  // A 1-D plane (one slice's row of columns_ cells), a segment of cells at a time: its boxes of
  // 5 cells whose first cell is in the segment, in order along the row (so the entropies keep
  // their sum's bits), and for each ε its cells' neighbours ε to the left and right. Each
  // segment is read once with a reach of up to a segment on either side (and the 4 cells its last
  // box needs), which holds the neighbours of every ε up to that reach: the row is read about 3
  // times, not once per ε. Only an ε beyond the reach (segments shorter than the largest ε)
  // reads its neighbours again.
  void line(std::int64_t s) {
    Tally* mine = per_slice_.empty() ? nullptr : &per_slice_[static_cast<std::size_t>(s)];
    const std::int64_t row = s * columns_;
    const std::int64_t reach = eps_.empty() ? 0 : std::min<std::int64_t>(segment_, eps_.back());
    std::vector<BasinLabel> window, left, right;
    for (std::int64_t first = 0; first < columns_; first += segment_) {
      const std::int64_t end = std::min(columns_, first + segment_);
      const std::int64_t lo = std::max<std::int64_t>(0, first - reach);
      const std::int64_t hi = std::min(columns_, end + std::max(reach, kBox - 1));
      read_cells(row + lo, row + hi, window);
      note_held({&window, &left, &right});
      const BasinLabel* segment = window.data() + (first - lo);
      count_cells(segment, row + first, row + end, mine);
      const std::int64_t first_box = (first + kBox - 1) / kBox * kBox;
      for (std::int64_t c0 = first_box; c0 < end && c0 + kBox <= columns_; c0 += kBox) {
        BoxCounts box;
        for (std::int64_t c = c0; c < c0 + kBox; ++c) box.add(segment[c - first]);
        add_box(box, box.entropy(static_cast<int>(kBox)), mine);
      }
      // Cells [a, b) of the row: from the window when it holds them, else read into `scratch`.
      const auto cells_at = [&](std::int64_t a, std::int64_t b,
                                std::vector<BasinLabel>& scratch) -> const BasinLabel* {
        if (a >= lo && b <= hi) return window.data() + (a - lo);
        read_cells(row + a, row + b, scratch);
        note_held({&window, &left, &right});
        return scratch.data();
      };
      for (std::size_t k = 0; k < eps_.size(); ++k) {
        const std::int64_t eps = eps_[k];
        const std::int64_t from = std::max(first, eps), to = std::min(end, columns_ - eps);
        if (from >= to) continue;
        const BasinLabel* here = segment + (from - first);
        const BasinLabel* before = cells_at(from - eps, to - eps, left);
        const BasinLabel* after = cells_at(from + eps, to + eps, right);
        std::int64_t uncertain = 0;
        for (std::int64_t i = 0; i < to - from; ++i)
          uncertain += before[i] != here[i] || after[i] != here[i];
        add_uncertain(k, to - from, uncertain, mine);
      }
    }
  }

  // Cells [begin, end) of the flat grid, into `cells`.
  void read_cells(std::int64_t begin, std::int64_t end, std::vector<BasinLabel>& cells) {
    fit(cells, end - begin);
    if (end > begin) read_(begin, end, cells.data());
  }

  void add_box(const BoxCounts& box, double entropy, Tally* mine) {
    for (Tally* t : {&whole_, mine}) {
      if (!t) continue;
      t->sum += entropy;
      ++t->boxes;
      if (box.counts.size() > 1) t->boundary_sum += entropy, ++t->boundary_boxes;
    }
  }

  void add_uncertain(std::size_t k, std::int64_t cells, std::int64_t uncertain, Tally* mine) {
    for (Tally* t : {&whole_, mine}) {
      if (!t) continue;
      t->eps_cells[k] += cells;
      t->eps_uncertain[k] += uncertain;
    }
  }

  // A 2-D plane (one slice), a band of rows at a time, then its Wada test.
  void slice(std::int64_t s) {
    Tally* mine = per_slice_.empty() ? nullptr : &per_slice_[static_cast<std::size_t>(s)];
    std::vector<BasinLabel> band, above, below;
    std::vector<std::int32_t> basins;
    for (std::int64_t first = 0; first < rows_; first += strip_) {
      const std::int64_t end = std::min(rows_, first + strip_);
      // The band: its rows and those its last boxes reach below it.
      const std::int64_t band_end = std::min(rows_, end + kBox - 1);
      read_rows(s, first, band_end, band);
      note_held({&band, &above, &below});
      count_cells(band.data(), flat(s, first), flat(s, end), mine);
      wada_detail::collect_basins(band.data(), static_cast<std::size_t>((end - first) * columns_), basins);
      boxes(band.data(), first, end, mine);
      for (std::size_t k = 0; k < eps_.size(); ++k) uncertain(s, k, band, first, end, above, below, mine);
    }
    // The ε bands are done with: the Wada pass holds one band and its masks, no more
    // (summary_bytes_on_rank0 counts the larger of the two passes, not their sum).
    std::vector<BasinLabel>().swap(above);
    std::vector<BasinLabel>().swap(below);
    std::sort(basins.begin(), basins.end());
    basins.erase(std::unique(basins.begin(), basins.end()), basins.end());
    if (basins.size() < 3) return;
    WadaTest wada;
    if (basins.size() > static_cast<std::size_t>(kWadaMaxBasins)) {
      wada.planes_too_many = 1;
    } else {
      wada.planes_tested = 1;
      for (std::int64_t first = 0; first < rows_; first += strip_) {
        const std::int64_t end = std::min(rows_, first + strip_);
        const std::int64_t band_first = std::max<std::int64_t>(0, first - wada_detail::kHalo);
        read_rows(s, band_first, std::min(rows_, end + wada_detail::kHalo), band);
        note_held({&band});
        wada_detail::count_rows(band.data(), band_first, rows_, columns_, first, end, basins, wada);
      }
    }
    add_wada(whole_.wada, wada);
    if (mine) add_wada(mine->wada, wada);
  }

  // The boxes whose first row is in [first, end): over the bands, slice by slice, row of boxes by
  // row, column by column, whatever the band height (the sum of their entropies keeps its bits).
  void boxes(const BasinLabel* band, std::int64_t first, std::int64_t end, Tally* mine) {
    for (std::int64_t r0 = (first + kBox - 1) / kBox * kBox; r0 < end && r0 + kBox <= rows_; r0 += kBox)
      for (std::int64_t c0 = 0; c0 + kBox <= columns_; c0 += kBox) {
        BoxCounts box;
        for (std::int64_t r = r0; r < r0 + kBox; ++r)
          for (std::int64_t c = c0; c < c0 + kBox; ++c) box.add(band[(r - first) * columns_ + c]);
        add_box(box, box.entropy(static_cast<int>(kBox * kBox)), mine);
      }
  }

  // The rows [first, end) of a slice, from the band when it holds them, else read.
  const BasinLabel* rows_at(std::int64_t s, std::int64_t from, std::int64_t to,
                            const std::vector<BasinLabel>& band, std::int64_t band_first,
                            std::vector<BasinLabel>& scratch, const std::vector<BasinLabel>& other) {
    const std::int64_t band_end = band_first + static_cast<std::int64_t>(band.size()) / std::max<std::int64_t>(columns_, 1);
    if (from >= band_first && to <= band_end) return band.data() + (from - band_first) * columns_;
    read_rows(s, from, to, scratch);
    note_held({&band, &scratch, &other});
    return scratch.data();
  }

  // Cells of rows [first, end) with every neighbour ε away inside the plane: uncertain if one
  // of them differs (BasinStatistics::uncertain_fraction, as counts).
  void uncertain(std::int64_t s, std::size_t k, const std::vector<BasinLabel>& band, std::int64_t first,
                 std::int64_t end, std::vector<BasinLabel>& above, std::vector<BasinLabel>& below, Tally* mine) {
    const std::int64_t eps = eps_[k];
    const std::int64_t from = std::max(first, eps), to = std::min(end, rows_ - eps);
    if (from >= to || columns_ - eps <= eps) return;
    const BasinLabel* here = band.data() + (from - first) * columns_;
    const BasinLabel* up = rows_at(s, from - eps, to - eps, band, first, above, below);
    const BasinLabel* down = rows_at(s, from + eps, to + eps, band, first, below, above);
    std::int64_t cells = 0, uncertain = 0;
    for (std::int64_t r = 0; r < to - from; ++r)
      for (std::int64_t c = eps; c < columns_ - eps; ++c) {
        const std::int64_t i = r * columns_ + c;
        const bool differs = here[i - eps] != here[i] || here[i + eps] != here[i] ||
                             up[i] != here[i] || down[i] != here[i];
        ++cells;
        uncertain += differs;
      }
    add_uncertain(k, cells, uncertain, mine);
  }

  const BasinMapShape& shape_;
  const LabelReader& read_;
  StripOptions options_;
  std::int64_t slices_ = 1, rows_ = 1, columns_ = 1, strip_ = 1, segment_ = 1;
  std::vector<int> eps_;
  std::int64_t stride_ = 1, values_ = 0;
  std::vector<LabelCounts> along_;
  Tally whole_;
  std::vector<Tally> per_slice_;
  std::int64_t most_held_ = 0;
};

}  // namespace

MapStatistics strip_statistics(const BasinMapShape& shape, const LabelReader& read,
                               const StripOptions& options) {
  return StripPass(shape, read, options).run();
}

}  // namespace cs
