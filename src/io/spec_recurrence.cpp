// measures.basin's keys of the recurrence mapper (RecurrenceSettings; README, "Basins of any
// system"): whether it runs, the cells' size, the thresholds of its state machine, its box.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <string>

#include "io/spec_reader.hpp"
#include "io/spec_suggestions.hpp"

namespace cs::spec {
namespace {

constexpr std::string_view kPrefix = "measures.basin";

}  // namespace

void SpecReader::read_basin_recurrence(const toml::table& t, RecurrenceSettings& r) {
  if (const toml::node* on = t.get("recurrence"))
    r.enabled = boolean(*on, fmt::format("{}.recurrence", kPrefix));
  if (const toml::node* size = t.get("cell_size")) {
    const std::string key = fmt::format("{}.cell_size", kPrefix);
    r.cell_size = number(*size, key);
    if (!(*r.cell_size > 0.0))
      fail_value(*size, key, "a cell's side > 0 (in the variables' units)");
  }
  const auto count = [&](const char* name, std::int64_t& value, std::string_view meaning) {
    const toml::node* node = t.get(name);
    if (node == nullptr) return;
    const std::string key = fmt::format("{}.{}", kPrefix, name);
    value = integer(*node, key);
    if (value < 1) fail_value(*node, key, meaning);
  };
  count("recurrences", r.recurrences, "an integer >= 1 (revisits in a row that find an attractor)");
  count("locate", r.locate, "an integer >= 1 (samples that locate the attractor's cells)");
  count("max_cells", r.max_cells, "an integer >= 1 (cells a lane may visit)");
  if (const toml::node* box = t.get("box")) {
    const std::string key = fmt::format("{}.box", kPrefix);
    Names phase_space;
    for (const auto& v : scene_->variables)
      if (v.name != "z" && v.name != "lambda") phase_space.push_back(v.name);
    for (const auto& [name, value] : table(*box, key)) {
      const std::string var(name.str()), item = fmt::format("{}.{}", key, var);
      if (!contains(phase_space, var))
        fail(&value, fmt::format("{}: '{}' is not a position or momentum of scene '{}' ({}){}",
                                 item, var, scene_->name, fmt::join(phase_space, ", "),
                                 did_you_mean(var, phase_space, "")));
      const std::vector<double> range = numbers(value, item);
      if (range.size() != 2 || !(range[0] < range[1]))
        fail(&value, fmt::format("{}: expected [lo, hi] with lo < hi", item));
      r.box[var] = {range[0], range[1]};
    }
  }
}

}  // namespace cs::spec
