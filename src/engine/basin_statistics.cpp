#include "engine/basin_statistics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <limits>
#include <numeric>

namespace cs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The grid as slices (every axis before the plane, flattened) of a plane rows × columns
// (rows = 1 for a 1-D plane).
struct Planes {
  std::int64_t slices = 1, rows = 1, columns = 1;
  explicit Planes(const BasinMapShape& s) {
    const auto n = s.dims.size();
    const auto first_plane_axis = n - static_cast<std::size_t>(s.plane_axes);
    for (std::size_t a = 0; a < first_plane_axis; ++a) slices *= s.dims[a];
    if (s.plane_axes >= 1) columns = s.dims[n - 1];
    if (s.plane_axes == 2) rows = s.dims[n - 2];
  }
  std::int64_t at(std::int64_t slice, std::int64_t r, std::int64_t c) const {
    return (slice * rows + r) * columns + c;
  }
};

using basin_detail::BoxCounts;

void box_entropies(const std::vector<BasinLabel>& labels, const Planes& g, int plane_axes,
                   BasinStatistics& out) {
  const int e = out.box_cells;
  const std::int64_t box_rows = plane_axes == 2 ? e : 1;
  double sum = 0.0, boundary_sum = 0.0;
  for (std::int64_t s = 0; s < g.slices; ++s)
    for (std::int64_t r0 = 0; r0 + box_rows <= g.rows; r0 += box_rows)
      for (std::int64_t c0 = 0; c0 + e <= g.columns; c0 += e) {
        BoxCounts box;
        for (std::int64_t r = r0; r < r0 + box_rows; ++r)
          for (std::int64_t c = c0; c < c0 + e; ++c) box.add(labels[static_cast<std::size_t>(g.at(s, r, c))]);
        const double entropy = box.entropy(static_cast<int>(box_rows * e));
        sum += entropy;
        ++out.boxes;
        if (box.counts.size() > 1) boundary_sum += entropy, ++out.boundary_boxes;
      }
  out.basin_entropy = out.boxes > 0 ? sum / static_cast<double>(out.boxes) : kNaN;
  out.boundary_basin_entropy =
      out.boundary_boxes > 0 ? boundary_sum / static_cast<double>(out.boundary_boxes) : kNaN;
}

// Cells with all four (two, in 1-D) neighbours ε away inside the grid; uncertain if one of them
// differs.
double uncertain_fraction(const std::vector<BasinLabel>& labels, const Planes& g, int plane_axes,
                          std::int64_t eps) {
  std::int64_t cells = 0, uncertain = 0;
  const std::int64_t row_eps = plane_axes == 2 ? eps : 0;
  for (std::int64_t s = 0; s < g.slices; ++s)
    for (std::int64_t r = row_eps; r < g.rows - row_eps; ++r)
      for (std::int64_t c = eps; c < g.columns - eps; ++c) {
        const auto here = labels[static_cast<std::size_t>(g.at(s, r, c))];
        bool differs = labels[static_cast<std::size_t>(g.at(s, r, c - eps))] != here ||
                       labels[static_cast<std::size_t>(g.at(s, r, c + eps))] != here;
        if (plane_axes == 2)
          differs = differs || labels[static_cast<std::size_t>(g.at(s, r - eps, c))] != here ||
                    labels[static_cast<std::size_t>(g.at(s, r + eps, c))] != here;
        ++cells;
        uncertain += differs;
      }
  return cells > 0 ? static_cast<double>(uncertain) / static_cast<double>(cells) : kNaN;
}

}  // namespace

namespace basin_detail {

// Least-squares slope of log f against log ε over the points with f > 0.
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

}  // namespace basin_detail

using basin_detail::log_log_slope;

BasinStatistics basin_statistics(const std::vector<BasinLabel>& labels,
                                 const BasinMapShape& shape) {
  BasinStatistics out;
  out.points = static_cast<std::int64_t>(labels.size());
  // Labels run from -1 (the double well's left well) to the number of attractors.
  BasinLabel lowest = 0, highest = 0;
  for (auto l : labels) lowest = std::min(lowest, l), highest = std::max(highest, l);
  std::vector<std::int64_t> per_label(static_cast<std::size_t>(std::int64_t{highest} - lowest + 1));
  for (auto l : labels) ++per_label[static_cast<std::size_t>(l - lowest)];
  for (std::size_t k = 0; k < per_label.size(); ++k)
    if (per_label[k] > 0) out.cells[static_cast<int>(lowest + static_cast<BasinLabel>(k))] = per_label[k];
  if (shape.plane_axes == 0) {
    out.basin_entropy = out.boundary_basin_entropy = kNaN;
    out.uncertainty_exponent = out.boundary_dimension = kNaN;
    return out;
  }
  const Planes g(shape);
  box_entropies(labels, g, shape.plane_axes, out);
  const std::int64_t smallest_side = shape.plane_axes == 2 ? std::min(g.rows, g.columns) : g.columns;
  for (std::int64_t eps = 1; 8 * eps <= smallest_side; eps *= 2) {
    out.epsilon_cells.push_back(static_cast<int>(eps));
    out.uncertain_fraction.push_back(uncertain_fraction(labels, g, shape.plane_axes, eps));
  }
  out.uncertainty_exponent = log_log_slope(out.epsilon_cells, out.uncertain_fraction);
  out.boundary_dimension = shape.plane_axes - out.uncertainty_exponent;
  if (shape.plane_axes == 2) out.wada = wada_test(labels, g.slices, g.rows, g.columns);
  return out;
}

std::vector<std::map<int, double>> fractions_along(const std::vector<BasinLabel>& labels,
                                                   const BasinMapShape& shape, int axis) {
  std::int64_t stride = 1;
  for (std::size_t a = static_cast<std::size_t>(axis) + 1; a < shape.dims.size(); ++a)
    stride *= shape.dims[a];
  const std::int64_t n = shape.dims[static_cast<std::size_t>(axis)];
  std::vector<std::map<int, double>> fractions(static_cast<std::size_t>(n));
  std::vector<std::int64_t> totals(static_cast<std::size_t>(n), 0);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const auto v = static_cast<std::size_t>((static_cast<std::int64_t>(i) / stride) % n);
    fractions[v][labels[i]] += 1.0;
    ++totals[v];
  }
  for (std::size_t v = 0; v < fractions.size(); ++v)
    for (auto& [label, f] : fractions[v]) f /= static_cast<double>(totals[v]);
  return fractions;
}

}  // namespace cs
