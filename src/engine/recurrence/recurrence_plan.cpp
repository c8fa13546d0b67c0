#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/recurrence/cell_grid.hpp"
#include "engine/recurrence/default_range.hpp"
#include "engine/recurrence/recurrence_search.hpp"
#include "engine/scene_form.hpp"

namespace cs {

std::array<double, 2> default_range(const RunSpec& spec, const std::string& name) {
  const auto initial = spec.initial.find(name);
  double lo = initial == spec.initial.end() ? 0.0 : initial->second, hi = lo;
  for (const auto& axis : spec.axes)
    if (!axis.is_parameter && !axis.is_step_size && axis.target == name)
      for (double v : axis.values) lo = std::min(lo, v), hi = std::max(hi, v);
  const double widen = 0.5 * std::max(hi - lo, 1.0);
  return {lo - widen, hi + widen};
}

RecurrenceSearch plan_recurrence(const RunSpec& spec, const SceneInfo& scene,
                                 const std::vector<double>& angle_period) {
  RecurrenceSearch r;
  const RecurrenceSettings& s = spec.measures.basin->recurrence;
  r.period_on_autonomous = spec.measures.basin->period.has_value() && !reads_time(spec, scene);
  // K in the energy trap's form has fixed points alone for attractors (scene_form.hpp), which
  // the anchor test and the trap find.
  r.enabled = s.enabled.value_or(!energy_trap_form(spec, scene));
  if (!r.enabled) {
    r.why_off = s.enabled ? "measures.basin.recurrence = false"
                          : "K = p^2/2 + V(q) + k*z without t: every attractor is a fixed point";
    return r;
  }
  r.recurrences = s.recurrences;
  r.locate = s.locate;
  r.max_cells = s.max_cells;
  const int n = 2 * scene.dof;
  double widest = 0.0;
  for (int k = 0; k < n; ++k) {
    const std::string& name = scene.variables[static_cast<std::size_t>(k)].name;
    const double period = angle_period[static_cast<std::size_t>(k)];
    const auto given = s.box.find(name);
    const std::array<double, 2> range = period > 0.0           ? std::array<double, 2>{0.0, period}
                                        : given != s.box.end() ? given->second
                                                               : default_range(spec, name);
    r.lower.push_back(range[0]);
    r.upper.push_back(range[1]);
    r.angle_period.push_back(period);
    widest = std::max(widest, range[1] - range[0]);
  }
  const double size = s.cell_size.value_or(widest / RecurrenceSettings::kDefaultCellsAcross);
  double keys = 1.0;
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double cells = cells_along(r.lower[i], r.upper[i], size, r.angle_period[i]);
    r.cells.push_back(static_cast<std::int64_t>(cells));
    r.cell_size.push_back(r.angle_period[i] > 0.0 ? r.angle_period[i] / cells : size);
    keys *= cells;
  }
  if (!(keys <= 9007199254740992.0))
    throw InputError(
        fmt::format("measures.basin.cell_size = {}: the box holds {:.3g} cells, more "
                    "than 2^53; use larger cells or a smaller measures.basin.box",
                    size, keys));
  return r;
}

std::vector<double> cell_centre(const RecurrenceSearch& r, std::uint64_t key) {
  std::vector<double> centre;
  for (std::size_t k = 0; k < r.cells.size(); ++k) {
    const auto n = static_cast<std::uint64_t>(r.cells[k]);
    centre.push_back(r.lower[k] + (static_cast<double>(key % n) + 0.5) * r.cell_size[k]);
    key /= n;
  }
  return centre;
}

}  // namespace cs
