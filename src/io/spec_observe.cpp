// [measures] observe, observe_window and stop: measures as formulas (docs/observables.md), each
// formula checked against the scene by K's parser (formula/measure_formulas.hpp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cctype>
#include <string>

#include "formula/measure_formulas.hpp"
#include "io/spec_reader.hpp"
#include "io/spec_suggestions.hpp"

namespace cs::spec {
namespace {

bool identifier(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

}  // namespace

void SpecReader::read_observe(const toml::table& measures) {
  const toml::node* node = measures.get("observe");
  const toml::node* window = measures.get("observe_window");
  if (node == nullptr) {
    if (window != nullptr)
      fail(window, "measures.observe_window: a window over which observables are averaged; give "
                   "measures.observe = { name = \"formula\", ... } too");
    return;
  }
  const toml::table& list = table(*node, "measures.observe");
  if (list.empty())
    fail_value(*node, "measures.observe", "at least one observable { name = \"formula\" }");
  ObserveMeasure observe;
  Names reserved = variable_names(*scene_);
  for (const char* name : {"log_lambda", "H", "t", "time"}) reserved.emplace_back(name);
  for (const auto& [key, value] : list) {
    const std::string name(key.str());
    const std::string path = fmt::format("measures.observe.{}", name);
    if (!identifier(name))
      fail(&value, fmt::format("{}: an observable's name is a letter, then letters, digits and "
                               "'_' (it names the datasets final_{}, traj_{}, ...)",
                               path, name, name));
    if (contains(reserved, name))
      fail(&value, fmt::format("{}: '{}' would name the datasets final_{} / traj_{} of a "
                               "quantity the file already has (or may have); name the "
                               "observable otherwise",
                               path, name, name, name));
    const std::string text = string(value, path);
    try {
      check_measure_formula(path, text, *scene_);
    } catch (const InputError& e) {
      fail(&value, e.what());
    }
    observe.formulas.emplace_back(name, text);
  }
  if (window != nullptr) {
    const std::string key = "measures.observe_window";
    const toml::table& w = table(*window, key);
    check_keys(w, key, {"from", "to"});
    const toml::node* from = w.get("from");
    const toml::node* to = w.get("to");
    if (from == nullptr || to == nullptr)
      fail(window, fmt::format("{}: give both ends, {{ from = ..., to = ... }}", key));
    const double a = number(*from, key + ".from"), b = number(*to, key + ".to");
    // The message is placed at the end out of range (a --set of it names the argument), at the
    // table when the ends are in the wrong order.
    const toml::node* at = !(spec_.t_start <= a) ? from : !(b <= spec_.t_end) ? to : window;
    if (!(spec_.t_start <= a && a <= b && b <= spec_.t_end))
      fail(at, fmt::format("{} = {{ from = {}, to = {} }}: expected {} <= from <= to <= "
                               "t_end = {}",
                               key, a, b,
                               spec_.t_start == 0.0 ? std::string("0")
                                                    : fmt::format("t_start = {}", spec_.t_start),
                               spec_.t_end));
    observe.window = std::array<double, 2>{a, b};
  }
  spec_.measures.observe = std::move(observe);
}

void SpecReader::read_stop(const toml::table& measures) {
  const toml::node* node = measures.get("stop");
  if (node == nullptr) return;
  const std::string key = "measures.stop";
  const toml::table& t = table(*node, key);
  check_keys(t, key, {"when", "label", "exits"});
  const toml::node* when = t.get("when");
  if (when == nullptr)
    fail(node, fmt::format("{}: give the condition, {{ when = \"q1^2 + q2^2 > 4\" }}", key));
  StopMeasure stop;
  stop.when = string(*when, key + ".when");
  try {
    check_condition(key + ".when", stop.when, *scene_);
  } catch (const InputError& e) {
    fail(when, e.what());
  }
  const toml::node* label = t.get("label");
  const toml::node* exits = t.get("exits");
  if (label != nullptr && exits != nullptr)
    fail(exits, fmt::format("{}: give the exit channel either as a formula (label) or as "
                            "conditions (exits), not both",
                            key));
  if (label != nullptr) {
    stop.label = string(*label, key + ".label");
    try {
      check_measure_formula(key + ".label", stop.label, *scene_);
    } catch (const InputError& e) {
      fail(label, e.what());
    }
  }
  if (exits != nullptr) {
    const toml::array& list = array(*exits, key + ".exits");
    if (list.empty() || list.size() > 100)
      fail_value(*exits, key + ".exits", "from 1 to 100 conditions, one per exit channel");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = fmt::format("{}.exits[{}]", key, i);
      std::string text = string(*list.get(i), at);
      try {
        check_condition(at, text, *scene_);
      } catch (const InputError& e) {
        fail(list.get(i), e.what());
      }
      stop.exits.push_back(std::move(text));
    }
  }
  spec_.measures.stop = std::move(stop);
}

}  // namespace cs::spec
