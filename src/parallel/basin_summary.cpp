#include "parallel/basin_summary.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <functional>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/attractor_continuation.hpp"
#include "engine/basin_column.hpp"
#include "engine/fixed_point_exponent.hpp"
#include "engine/recurrence/lane_records.hpp"
#include "engine/strip_statistics.hpp"
#include "mpi/comm.hpp"
#include "parallel/undecided_summary.hpp"
#include "physics/energy_wells.hpp"

namespace cs {
namespace {

// The plane of initial conditions: the last two axes if both set initial values, else the last
// one if it does; the axes before it are slices (a parameter, h).
BasinMapShape map_shape(const RunSpec& spec) {
  BasinMapShape shape;
  for (const auto& axis : spec.axes) shape.dims.push_back(static_cast<std::int64_t>(axis.values.size()));
  const auto initial = [&](std::size_t from_end) {
    if (spec.axes.size() < from_end) return false;
    const auto& axis = spec.axes[spec.axes.size() - from_end];
    return !axis.is_parameter && !axis.is_step_size;
  };
  shape.plane_axes = initial(1) ? (initial(2) ? 2 : 1) : 0;
  return shape;
}

int first_parameter_axis(const RunSpec& spec) {
  for (std::size_t a = 0; a < spec.axes.size(); ++a)
    if (spec.axes[a].is_parameter) return static_cast<int>(a);
  return -1;
}

// Collective. Whether the energy trap served the lanes (energy_wells.hpp, TrapVerdict), from
// each block's count of its lanes' verdicts: "used", or "not used: why", or both with their counts.
std::string energy_trap_verdict(const RunPlan& whole,
                                const std::vector<std::unique_ptr<BlockResults>>& results,
                                MPI_Comm comm) {
  if (whole.map.trap_verdict < 0) return "not used: measures.basin.exact_trap = false";
  constexpr int kVerdicts = kTrapVerdicts;
  std::int64_t counts[kVerdicts] = {};
  for (const auto& block : results) {
    const auto& column = block->columns[static_cast<std::size_t>(whole.map.trap_verdict)];
    for (int v = 0; v < kVerdicts; ++v) counts[v] += static_cast<std::int64_t>(column[static_cast<std::size_t>(v)]);
  }
  allreduce(comm, counts, kVerdicts, MPI_INT64_T, MPI_SUM);
  static const char* const why[kVerdicts] = {
      "K is not p^2/2 + V(q) + k*z without t, so no energy is known never to rise",
      "",
      "no dissipation: the coefficient k of z in K is not negative, so the energy may rise",
      "no minimum of V was found in the box around the map's positions",
      "V on the boundary of the box around the map's positions is nowhere above its lowest "
      "minimum",
      "no saddle of V lies above its lowest minimum by more than the integrator's energy margin "
      "(a smaller h helps)"};
  const std::int64_t used = counts[static_cast<int>(TrapVerdict::used)];
  std::int64_t total = 0;
  for (auto n : counts) total += n;
  if (used == total) return "used";
  std::vector<std::string> reasons;
  for (int v = 0; v < kVerdicts; ++v)
    if (v != static_cast<int>(TrapVerdict::used) && counts[v] > 0)
      reasons.push_back(counts[v] == total - used && used == 0
                            ? std::string(why[v])
                            : fmt::format("{} ({} cells)", why[v], counts[v]));
  if (used == 0) return "not used: " + fmt::format("{}", fmt::join(reasons, "; "));
  return fmt::format("used for {} of {} cells; not for the others: {}", used, total,
                     fmt::join(reasons, "; "));
}

// Where each attractor is at each value of the continuation axis, NaN where it is not found:
// branch_<var>(axis, attractor), so that a figure can draw the branches.
void add_branches(const BasinSummary& basins, const RunPlan& plan, FileLayout& layout) {
  const std::string axis = plan.spec.axes.front().name;
  for (int k = 0; k < 2 * plan.scene.dof; ++k) {
    const VariableInfo& v = plan.scene.variables[static_cast<std::size_t>(k)];
    std::vector<double> values;
    for (const auto& at_value : basins.along)
      for (const Attractor& branch : basins.table) {
        const auto it = std::find_if(at_value.begin(), at_value.end(),
                                     [&](const Attractor& a) { return a.label == branch.label; });
        values.push_back(it == at_value.end() ? std::nan("") : it->point[static_cast<std::size_t>(k)]);
      }
    layout.tables.push_back({{"branch_" + v.name, ElementType::float64, false,
                              v.description + " at a point of the attractor at this " + axis +
                                  " (NaN where it is not found)",
                              "", {}, "", std::nullopt},
                             {axis, "attractor"},
                             std::move(values)});
  }
}

// Each attractor's description (attractor_analysis.hpp): kind, λ₁, period in time, samples
// along it over (attractor, point, var). Values where it was computed (rank 0 after the run),
// NaN for the names declared before the run.
void add_analysis_to_layout(const BasinSummary& basins, const RunPlan& plan, FileLayout& layout) {
  const std::size_t n = basins.table.size(), vars = static_cast<std::size_t>(2 * plan.scene.dof);
  const bool known = basins.analysis.size() == n;
  std::vector<double> kind, lyapunov, period, points;
  for (std::size_t a = 0; a < n; ++a) {
    const AttractorAnalysis* d = known ? &basins.analysis[a] : nullptr;
    kind.push_back(d ? static_cast<double>(d->kind) : 0.0);
    lyapunov.push_back(d ? d->lyapunov : std::nan(""));
    period.push_back(d ? d->time_period : std::nan(""));
    if (d) points.insert(points.end(), d->points.begin(), d->points.end());
    else points.resize(points.size() + kAttractorSamples * vars, std::nan(""));
  }
  std::vector<double> point_index(kAttractorSamples), var_index(vars);
  for (int k = 0; k < kAttractorSamples; ++k) point_index[static_cast<std::size_t>(k)] = k;
  std::string var_names;
  for (std::size_t k = 0; k < vars; ++k) {
    var_index[k] = static_cast<double>(k);
    var_names += fmt::format("{}{} {}", k ? ", " : "", k, plan.scene.variables[k].name);
  }
  layout.extra_dimensions.push_back(
      {"point", point_index, "sample along the attractor (in time order)", ""});
  layout.extra_dimensions.push_back(
      {"var", var_index, "phase-space variable: " + var_names, ""});
  const auto table = [&](DatasetSpec spec, std::vector<std::string> dims, std::vector<double> values) {
    layout.tables.push_back({std::move(spec), std::move(dims), std::move(values)});
  };
  table({"attractor_kind", ElementType::int8, false, "kind of the attractor", "", {0, 1, 2, 3, 4},
         kAttractorKindMeanings, std::nullopt},
        {"attractor"}, kind);
  table({"attractor_lyapunov", ElementType::float64, false,
         "largest Lyapunov exponent on the attractor (finite-time, integrator's step map)",
         "1/time", {}, "", std::nullopt},
        {"attractor"}, lyapunov);
  table({"attractor_time_period", ElementType::float64, false,
         "period of the attractor in time (NaN unless periodic)", "time", {}, "", std::nullopt},
        {"attractor"}, period);
  table({"attractor_points", ElementType::float64, false,
         "samples along the attractor (q.., p..; on the stroboscopic section if forced)", "", {},
         "", std::nullopt},
        {"attractor", "point", "var"}, points);
}

// The refused points for the summary: each distinct point (a continuation may meet one at every
// value) with its exact λ₁, the first few.
std::string refused_points(const std::vector<std::vector<Attractor>>& refused) {
  constexpr std::size_t kNamed = 3;
  std::vector<std::string> named;
  std::size_t count = 0;
  for (const auto& at_value : refused)
    for (const Attractor& a : at_value) {
      const std::string text =
          fmt::format("({:.4g}) with lambda_1 = {:+.4g}", fmt::join(a.point, ", "),
                      a.linearisation->lyapunov);
      if (std::find(named.begin(), named.end(), text) != named.end()) continue;
      ++count;
      if (named.size() < kNamed) named.push_back(text);
    }
  std::string text = fmt::format("{}", fmt::join(named, "; "));
  if (count > named.size()) text += fmt::format("; {} more", count - named.size());
  return text;
}

}  // namespace

BasinSummary summarise_basins(const RunPlan& whole,
                              std::vector<std::unique_ptr<BlockResults>>& results, MPI_Comm comm) {
  BasinSummary summary;
  std::vector<double> candidates;
  for (const auto& block : results) {
    const ExpandedBasin provisional(whole, *block);
    const std::vector<double> c = block_candidates(whole, *block);
    candidates.insert(candidates.end(), c.begin(), c.end());
  }
  // Every rank merges the same candidates and evaluates the same Jacobians: unstable fixed
  // points are refused alike, before the labels are final (attractor_table.hpp).
  AttractorTable table =
      merge_candidates(whole, gather(comm, candidates, true), &fixed_point_linearisation);
  summary.table = std::move(table.attractors);
  summary.labels = std::move(table.labels);
  summary.along = std::move(table.along);
  summary.refused = std::move(table.refused);
  for (const ElementType type : {ElementType::int8, ElementType::int16, ElementType::int32}) {
    summary.label_type = type;
    const double limit = type == ElementType::int8 ? 127.0 : type == ElementType::int16 ? 32767.0
                                                                                           : 2147483647.0;
    if (std::all_of(summary.table.begin(), summary.table.end(),
                    [&](const Attractor& a) { return a.label >= -limit && a.label <= limit; }))
      break;
  }
  // The undecided lanes per reason, counted as each block is labelled (its provisional values
  // name the reasons of its settled lanes: recurrence/lane_records.hpp).
  // A lane on a refused point settled, yet is on no attractor: count_undecided counts it as
  // such (reason `decided`, label 0), and it is counted apart, by why.
  std::vector<std::int64_t> undecided(kUndecidedReasons, 0);
  std::vector<double> provisional;
  std::int64_t refused = 0;
  for (auto& block : results) {
    const ExpandedBasin labels(whole, *block, true);
    if (whole.map.undecided_reason >= 0)
      provisional = block->columns[static_cast<std::size_t>(whole.map.basin)];
    const std::int64_t on_refused =
        label_block(whole, summary.table, *block, summary.along, summary.refused);
    std::vector<std::int64_t> here(kUndecidedReasons, 0);
    count_undecided(whole, *block, provisional, here.data());
    if (whole.map.undecided_reason >= 0) {
      if (here[0] < on_refused)  // never, short of a bug
        throw std::logic_error("a lane on a refused fixed point was not counted undecided");
      here[0] -= on_refused;
    }
    for (std::size_t r = 0; r < here.size(); ++r) undecided[r] += here[r];
    refused += on_refused;
  }
  summary.energy_trap = energy_trap_verdict(whole, results, comm);
  summary.undecided =
      undecided_reasons(whole, undecided, {refused, refused_points(summary.refused)}, comm);
  summary.continuation_axis = first_parameter_axis(whole.spec);
  return summary;
}

void add_statistics(const RunPlan& whole, BasinSummary& summary, const LabelReader& read) {
  const BasinMapShape shape = map_shape(whole.spec);
  StripOptions options;
  options.fractions_axis = summary.continuation_axis;
  // The usual layout (the parameter first, the plane last): S_b, S_bb and α per value too.
  options.per_slice = summary.continuation_axis == 0 && shape.plane_axes > 0 &&
                      shape.dims.size() == static_cast<std::size_t>(shape.plane_axes) + 1;
  MapStatistics s = strip_statistics(shape, read, options);
  summary.statistics = std::move(s.whole);
  summary.continuation = std::move(s.fractions);
  summary.continuation_statistics = std::move(s.per_slice);
}

double summary_bytes_on_rank0(const RunPlan& whole) {
  return summary_bytes_on_rank0(map_shape(whole.spec));
}

double summary_bytes_on_rank0(const BasinMapShape& shape) {
  if (shape.plane_axes == 0) {
    const std::int64_t points = std::accumulate(shape.dims.begin(), shape.dims.end(), std::int64_t{1},
                                                std::multiplies<>());
    return static_cast<double>(std::min(kStripCells, points)) * sizeof(BasinLabel);
  }
  const auto columns = shape.dims.back();
  // A 1-D plane's segment read with a segment's reach on either side and its last box's 4 cells
  // beyond, and the neighbours of an ε beyond that reach on either side (strip_statistics.cpp).
  if (shape.plane_axes == 1)
    return static_cast<double>(std::min(columns, 3 * kStripCells + 4) + 2 * std::min(columns, kStripCells)) *
           sizeof(BasinLabel);
  const std::int64_t rows = shape.dims[shape.dims.size() - 2];
  const std::int64_t strip = std::max<std::int64_t>(1, kStripCells / columns);
  // A band and its halos (strip_statistics.cpp): its labels and the two bands ε above and below
  // it, or, for the Wada test, its labels and two 64-bit masks and three bytes a cell.
  const auto band = static_cast<double>(std::min(rows, strip + 2 * wada_detail::kHalo) * columns);
  return band * std::max(3 * sizeof(BasinLabel), sizeof(BasinLabel) + 2 * sizeof(std::uint64_t) + 3);
}

void add_to_layout(const BasinSummary& basins, const RunPlan& plan, FileLayout& layout) {
  const auto& table = basins.table;
  const BasinStatistics& s = basins.statistics;
  std::vector<double> labels, periods, fractions, cells;
  for (const Attractor& a : table) {
    labels.push_back(a.label);
    periods.push_back(a.period);
    auto it = s.cells.find(a.label);
    const double n = it == s.cells.end() ? 0.0 : static_cast<double>(it->second);
    cells.push_back(n);
    fractions.push_back(n / static_cast<double>(s.points));
  }
  layout.extra_dimensions.push_back(
      {"attractor", labels, "label of the attractor (as in basin)", ""});
  const auto column = [&](std::string name, ElementType type, std::string long_name,
                          std::vector<double> values) {
    layout.tables.push_back({{std::move(name), type, false, std::move(long_name), "", {}, "",
                              std::nullopt},
                             {"attractor"},
                             std::move(values)});
  };
  column("attractor_label", basins.label_type, "label of the attractor in basin", labels);
  for (int k = 0; k < 2 * plan.scene.dof; ++k) {
    const VariableInfo& v = plan.scene.variables[static_cast<std::size_t>(k)];
    std::vector<double> values;
    for (const Attractor& a : table) values.push_back(a.point[static_cast<std::size_t>(k)]);
    column("attractor_" + v.name, ElementType::float64,
           v.description + " at a point of the attractor (on the stroboscopic section if forced)",
           values);
  }
  column("attractor_period", ElementType::int8,
         "period of the attractor on the stroboscopic map or looks (1: fixed point; -1: an exit "
         "of measures.stop, its channel in the first position's column)",
         periods);
  column("attractor_fraction", ElementType::float64, "fraction of the grid in its basin",
         fractions);
  column("attractor_cells", ElementType::float64, "grid points in its basin", cells);
  add_analysis_to_layout(basins, plan, layout);
  auto& number = layout.number_attributes;
  const auto undecided = s.cells.find(0);
  number["undecided_fraction"] =
      undecided == s.cells.end() ? 0.0
                                 : static_cast<double>(undecided->second) / static_cast<double>(s.points);
  number["basin_entropy"] = s.basin_entropy;
  number["boundary_basin_entropy"] = s.boundary_basin_entropy;
  number["basin_entropy_box_cells"] = s.box_cells;
  number["uncertainty_exponent"] = s.uncertainty_exponent;
  number["boundary_dimension"] = s.boundary_dimension;
  number["basin_tolerance"] = plan.attractors.tolerance;
  number["wada_touching_fraction"] = s.wada.touching_fraction();
  number["wada_merging_fraction"] = s.wada.covered_fraction(kWadaVerdictRadius);
  layout.text_attributes["wada"] = s.wada.verdict();
  layout.text_attributes["energy_trap"] = basins.energy_trap;
  if (!basins.undecided.empty()) layout.text_attributes["basin_undecided"] = basins.undecided;
  if (!basins.labels.description.empty())
    layout.text_attributes["basin_labels"] = basins.labels.description;
  layout.text_attributes["basin_boundary"] =
      std::isnan(s.boundary_basin_entropy) ? "no boundary on the map"
      : s.boundary_basin_entropy > std::numbers::ln2
          ? "fractal: boundary basin entropy > ln 2 (Daza et al. 2016)"
          : "not shown fractal: boundary basin entropy <= ln 2";
  if (!basins.along.empty()) add_branches(basins, plan, layout);
  if (basins.continuation_axis >= 0 && !basins.continuation.empty()) {
    const std::string axis = plan.spec.axes[static_cast<std::size_t>(basins.continuation_axis)].name;
    std::vector<double> f, u;
    for (const auto& at_value : basins.continuation) {
      for (const Attractor& a : table) {
        auto it = at_value.find(a.label);
        f.push_back(it == at_value.end() ? 0.0 : it->second);
      }
      auto it = at_value.find(0);
      u.push_back(it == at_value.end() ? 0.0 : it->second);
    }
    layout.tables.push_back({{"basin_fraction", ElementType::float64, false,
                              "fraction of the cells at this " + axis + " in each basin", "", {},
                              "", std::nullopt},
                             {axis, "attractor"},
                             f});
    layout.tables.push_back({{"basin_undecided_fraction", ElementType::float64, false,
                              "fraction of the cells at this " + axis + " left undecided", "",
                              {}, "", std::nullopt},
                             {axis},
                             u});
    const auto per_value = [&](std::string name, std::string long_name, auto field) {
      std::vector<double> values;
      for (const BasinStatistics& at_value : basins.continuation_statistics)
        values.push_back(field(at_value));
      layout.tables.push_back({{std::move(name), ElementType::float64, false,
                                std::move(long_name), "", {}, "", std::nullopt},
                               {axis},
                               std::move(values)});
    };
    if (!basins.continuation_statistics.empty()) {
      per_value("basin_entropy", "basin entropy S_b of the map at this " + axis,
                [](const BasinStatistics& b) { return b.basin_entropy; });
      per_value("boundary_basin_entropy", "boundary basin entropy S_bb of the map at this " + axis,
                [](const BasinStatistics& b) { return b.boundary_basin_entropy; });
      per_value("uncertainty_exponent", "uncertainty exponent of the map at this " + axis,
                [](const BasinStatistics& b) { return b.uncertainty_exponent; });
      per_value("wada_merging_fraction",
                fmt::format("fraction of the boundary cells at this {} within {} cells of every "
                            "merged basin's boundary (Wada test)",
                            axis, kWadaVerdictRadius),
                [](const BasinStatistics& b) { return b.wada.covered_fraction(kWadaVerdictRadius); });
    }
  }
}

void add_names_to_layout(const RunPlan& plan, FileLayout& layout) {
  BasinSummary names;
  names.continuation_axis = first_parameter_axis(plan.spec);
  const BasinMapShape shape = map_shape(plan.spec);
  if (names.continuation_axis >= 0) names.continuation.resize(1);
  if (continuation_axis(plan).along_parameter) names.along.resize(1);
  if (names.continuation_axis == 0 && shape.plane_axes > 0 &&
      shape.dims.size() == static_cast<std::size_t>(shape.plane_axes) + 1)
    names.continuation_statistics.resize(1);
  add_to_layout(names, plan, layout);
}

std::string describe(const BasinSummary& basins) {
  const BasinStatistics& s = basins.statistics;
  const auto fraction = [&](int label) {
    auto it = s.cells.find(label);
    return it == s.cells.end() ? 0.0 : static_cast<double>(it->second) / static_cast<double>(s.points);
  };
  std::string text = fmt::format("basins: {} attractor(s)", basins.table.size());
  for (const Attractor& a : basins.table)
    text += fmt::format("; {} ({}period {}) {:.4f}", a.label,
                        fmt::format("{:.4g}, ", fmt::join(a.point, ", ")), a.period, fraction(a.label));
  text += fmt::format("; undecided {:.4f}", fraction(0));
  if (!basins.undecided.empty()) text += fmt::format(" ({})", basins.undecided);
  text += fmt::format("; energy trap: {}", basins.energy_trap);
  if (!basins.labels.description.empty()) text += "; labels: " + basins.labels.description;
  if (!std::isnan(s.basin_entropy))
    text += fmt::format("; S_b = {:.4f}, S_bb = {:.4f} ({} ln 2: {}), uncertainty exponent {:.3f} "
                        "(boundary dimension {:.3f})",
                        s.basin_entropy, s.boundary_basin_entropy,
                        s.boundary_basin_entropy > std::numbers::ln2 ? ">" : "<=",
                        s.boundary_basin_entropy > std::numbers::ln2 ? "fractal boundary"
                                                                     : "not shown fractal",
                        s.uncertainty_exponent, s.boundary_dimension);
  if (s.wada.applies()) text += "; Wada test: " + s.wada.verdict();
  return text;
}

}  // namespace cs
