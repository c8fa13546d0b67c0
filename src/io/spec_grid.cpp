// [grid]: axes over scene parameters, initial values and the step size, in the spec's order.
#include "io/spec_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "io/linspace.hpp"
#include "io/memory_budget.hpp"

namespace cs::spec {

void SpecReader::read_grid() {
  const toml::node* node = doc_.get("grid");
  if (node == nullptr) return;
  check_keys(table(*node, "grid"), "grid", axis_names());
  std::vector<AxisDraft> drafts;
  for (const std::string& name : grid_order_)
    drafts.push_back(read_axis(name, *node->as_table()->get(name)));
  check_grid_size(drafts);
  for (AxisDraft& draft : drafts) {
    if (draft.n > 0) draft.axis.values = linspace(draft.from, draft.to, draft.n);
    check_axis_values(draft);
    // A parameter of K swept here and not valued under [scene] (read_custom_scene): the run's
    // base value is the axis's first, so every parameter has a finite value; each lane gets its
    // own from the axis.
    if (draft.axis.is_parameter && !spec_.parameters.contains(draft.axis.target))
      spec_.parameters[draft.axis.target] = draft.axis.values.front();
    spec_.axes.push_back(std::move(draft.axis));
  }
}

Names SpecReader::axis_names() const {
  Names names = parameter_names(*scene_);
  names.push_back("h");  // stability and accuracy maps over the step size
  for (const std::string& v : variable_names(*scene_)) names.push_back(v + "_0");
  return names;
}

SpecReader::AxisDraft SpecReader::read_axis(const std::string& name, const toml::node& node) const {
  const std::string key = "grid." + name;
  AxisDraft draft{GridAxis{name, name, true, false, {}}, &node};
  if (name == "h") {
    draft.axis.is_parameter = false;
    draft.axis.is_step_size = true;
  } else if (!contains(parameter_names(*scene_), name)) {
    draft.axis.target = name.substr(0, name.size() - 2);  // "q_0" -> "q"
    draft.axis.is_parameter = false;
  }
  if (!node.is_table())
    fail_type(node, key, "a table { from = ..., to = ..., n = ... } or { values = [...] }");
  const toml::table& t = *node.as_table();
  check_keys(t, key, {"from", "to", "n", "values"});
  if (t.contains("values")) {
    for (const char* part : {"from", "to", "n"})  // blame the key: it may come from --set
      if (const toml::node* extra = t.get(part))
        fail(extra, fmt::format("{}: give either {{ from, to, n }} or {{ values = [...] }}, "
                                "not both",
                                key));
    draft.axis.values = numbers(*t.get("values"), key + ".values");
    if (draft.axis.values.empty())
      fail_value(*t.get("values"), key + ".values", "a non-empty array of numbers");
    return draft;
  }
  for (const char* part : {"from", "to", "n"})
    if (!t.contains(part))
      fail(&node, fmt::format("{}: missing '{}'; an axis is {{ from = ..., to = ..., n = ... }} "
                              "(numpy.linspace) or {{ values = [...] }}",
                              key, part));
  draft.from = number(*t.get("from"), key + ".from");
  draft.to = number(*t.get("to"), key + ".to");
  draft.n = integer(*t.get("n"), key + ".n");
  if (draft.n < 1 || draft.n > kMaxAxisPoints)
    fail_value(*t.get("n"), key + ".n",
               fmt::format("an integer from 1 to 2^32 = {}", kMaxAxisPoints));
  return draft;
}

void SpecReader::check_grid_size(const std::vector<AxisDraft>& drafts) const {
  std::int64_t points = 1;
  for (const AxisDraft& draft : drafts) {
    if (draft.size() > kMaxGridPoints / points) {
      Names sizes;
      for (const AxisDraft& d : drafts)
        sizes.push_back(fmt::format("{} = {}", d.axis.name, d.size()));
      fail(doc_.get("grid"), fmt::format("the grid has more than 2^40 = {} points ({}); "
                                         "split the sweep into several runs",
                                         kMaxGridPoints, fmt::join(sizes, " x ")));
    }
    points *= draft.size();
  }
  // Before linspace fills anything: the coordinates, and at least one byte a point (results
  // stream into the file as blocks finish; a basin map keeps its compact labels to the end:
  // check_resources in sweep.cpp refines this once the measures are known).
  double bytes = static_cast<double>(points);
  for (const AxisDraft& draft : drafts) bytes += static_cast<double>(draft.size()) * sizeof(double);
  if (const MemoryBudget budget = memory_budget(); bytes > 0.8 * budget.bytes)
    fail(doc_.get("grid"),
         fmt::format("the grid has {} points and needs at least {:.3g} GiB of memory, but {:.3g} "
                     "GiB is available ({}); use a coarser grid or split the sweep",
                     points, bytes / 1073741824.0, budget.bytes / 1073741824.0, budget.source));
}

void SpecReader::check_axis_values(const AxisDraft& draft) const {
  const std::string key = "grid." + draft.axis.name;
  for (const double value : draft.axis.values) {
    if (!std::isfinite(value))  // linspace over a range wider than the largest double
      fail_value(*draft.node, key, "from and to whose difference is a finite number");
    if (must_be_positive(draft.axis.target) && !(value > 0.0))
      fail_value(*draft.node, key,
                 fmt::format("values > 0 ({} must be positive)", draft.axis.target));
    if (draft.axis.is_step_size) check_step_size(draft, value);
  }
}

void SpecReader::check_step_size(const AxisDraft& draft, double h) const {
  if (!spec_.axes.empty())
    fail(draft.node, "grid.h must be the first grid axis (each step size is integrated as "
                     "its own slice of the grid)");
  if (!(h > 0.0)) fail_value(*draft.node, "grid.h", "step sizes > 0");
  const double duration = spec_.t_end - spec_.t_start, ratio = duration / h;
  const auto steps = std::llround(ratio);
  if (!(ratio >= 1.0 && ratio < 9.007199254740992e15) ||
      std::abs(static_cast<double>(steps) * h - duration) > kStepTolerance * duration)
    fail(draft.node, fmt::format("grid.h = {}: {} = {} is not a whole number of steps of it "
                                 "({} = {:.12g})",
                                 h, duration_name(), duration,
                                 spec_.t_start == 0.0 ? "t_end / h" : "(t_end - t_start) / h",
                                 ratio));
}

}  // namespace cs::spec
