// Spec file -> RunSpec: TOML parsing (toml++), --set overrides, validation against the scene and
// method catalogs, and the canonical TOML text stored in the output. Decisions: spec_parser.hpp.
#include "io/spec_parser.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>

#include "io/memory_budget.hpp"
#include "numerics/method_catalog.hpp"
#include "formula/custom_scene.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

using Names = std::vector<std::string>;

// The engine flattens the grid into one int64 index and the output holds every point; 2^40 is
// far beyond any run that could finish, and checking it keeps the size product from overflowing.
constexpr std::int64_t kMaxGridPoints = std::int64_t{1} << 40;
// Every rank holds every coordinate vector: 2^32 doubles are already 32 GiB.
constexpr std::int64_t kMaxAxisPoints = std::int64_t{1} << 32;
// Beyond 2^53 steps a double can no longer count them (t = k h loses k).
constexpr double kMaxSteps = 9007199254740992.0;
// t_end is a whole number of steps when steps * h is within this of t_end, relative to t_end.
constexpr double kStepTolerance = 1e-9;

constexpr std::string_view kDefaultMethod = "hybrid_leapfrog";
// Source path given to the nodes parsed from a --set argument, so messages can name it.
constexpr std::string_view kSetPrefix = "--set ";

// The sections in the order spec_text writes them.
constexpr std::string_view kSections[] = {"scene", "initial", "integrator", "grid", "measures"};
// spec_text writes these keys first, in this order, wherever they occur; the rest by name.
constexpr std::string_view kLeadKeys[] = {"name", "method", "h", "t_end", "from", "to", "n"};

constexpr std::string_view kMeasureNames[] = {"final_state", "trajectory", "basin", "sync"};

// Names users bring from other tools, which edit distance alone would not find.
// clang-format off
constexpr std::pair<std::string_view, std::string_view> kAliases[] = {
    {"dt", "h"}, {"step", "h"}, {"stepsize", "h"}, {"step_size", "h"}, {"timestep", "h"},
    {"time_step", "h"}, {"tmax", "t_end"}, {"t_max", "t_end"}, {"tfinal", "t_end"},
    {"t_final", "t_end"}, {"duration", "t_end"}, {"scheme", "method"}, {"integrator", "method"},
    {"algorithm", "method"}, {"model", "name"}, {"start", "from"}, {"stop", "to"}, {"end", "to"},
    {"num", "n"}, {"count", "n"}, {"points", "n"}, {"list", "values"}, {"stride", "every"},
    {"interval", "every"}, {"variables", "vars"}, {"final", "final_state"},
    {"traj", "trajectory"}, {"synchronization", "sync"}, {"basins", "basin"}};
// clang-format on

// ---------------------------------------------------------------------------------------------
// Small helpers

bool contains(const Names& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string dotted(std::string_view prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : fmt::format("{}.{}", prefix, key);
}

// Optimal string alignment distance: Levenshtein plus adjacent transpositions ("t_ned").
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// The candidate the user most likely meant, if any is close enough to be worth suggesting.
std::optional<std::string> closest(std::string_view key, const Names& candidates) {
  for (const auto& [alias, target] : kAliases)
    if (key == alias && contains(candidates, target)) return std::string(target);
  // An initial value and its grid axis differ only by "_0" (q <-> q_0).
  if (key.ends_with("_0") && contains(candidates, key.substr(0, key.size() - 2)))
    return std::string(key.substr(0, key.size() - 2));
  if (contains(candidates, std::string(key) + "_0")) return std::string(key) + "_0";
  // About one typo per three characters, and never a suggestion that shares nothing with key.
  const std::size_t limit = std::max<std::size_t>(1, key.size() / 3);
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(key, candidate);
    if (distance < best_distance && distance < key.size()) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

std::string did_you_mean(std::string_view key, const Names& candidates, std::string_view prefix) {
  const auto near = closest(key, candidates);
  return near ? fmt::format(" (did you mean '{}'?)", dotted(prefix, *near)) : "";
}

bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-';
  });
}

std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + '"';
}

Names keys_in_written_order(const toml::table& table) {
  Names keys;
  for (const std::string_view lead : kLeadKeys)
    if (table.contains(lead)) keys.emplace_back(lead);
  for (const auto& [key, value] : table)
    if (!contains(keys, key.str())) keys.emplace_back(key.str());
  return keys;
}

std::string key_text(std::string_view key) {
  return is_bare_key(key) ? std::string(key) : toml_string(key);
}

// Shortest text that reads back to the same double (std::to_chars), kept a TOML float.
std::string float_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";  // "3" would read as integer
  return text;
}

// A value in TOML's one-line syntax: used for spec_text and to show values in messages.
std::string inline_toml(const toml::node& node) {
  if (const auto* s = node.as_string()) return toml_string(s->get());
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return float_text(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = node.as_array()) {
    Names items;
    for (const toml::node& item : *a) items.push_back(inline_toml(item));
    return fmt::format("[{}]", fmt::join(items, ", "));
  }
  if (const auto* t = node.as_table()) {
    Names items;
    for (const std::string& key : keys_in_written_order(*t))
      items.push_back(fmt::format("{} = {}", key_text(key), inline_toml(*t->get(key))));
    return items.empty() ? "{}" : fmt::format("{{ {} }}", fmt::join(items, ", "));
  }
  std::ostringstream other;  // dates and times: never valid in a spec, but shown in messages
  node.visit([&](const auto& value) {
    if constexpr (requires { other << value.get(); }) other << value.get();
  });
  return other.str();
}

std::string shown(const toml::node& node) {
  constexpr std::size_t kMaxShown = 80;
  std::string text = inline_toml(node);
  return text.size() <= kMaxShown ? text : text.substr(0, kMaxShown - 3) + "...";
}

std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    default:
      return "a date/time";
  }
}

template <class Info>
Names names_of(const std::vector<Info>& infos) {
  Names names;
  for (const Info& info : infos) names.push_back(info.name);
  return names;
}

Names variable_names(const SceneInfo& scene) { return names_of(scene.variables); }
Names parameter_names(const SceneInfo& scene) { return names_of(scene.parameters); }

// lambda is an integrating factor and the kernel carries ln(lambda).
bool must_be_positive(std::string_view variable) { return variable == "lambda"; }

// ---------------------------------------------------------------------------------------------
// Validation: the parsed document (after --set) -> RunSpec

class SpecReader {
 public:
  SpecReader(const toml::table& doc, std::string_view source_name, Names grid_order)
      : doc_(doc), source_name_(source_name), grid_order_(std::move(grid_order)) {}

  RunSpec read() {
    check_keys(doc_, "", top_level_keys());
    read_scene();
    read_initial();
    read_integrator();
    read_grid();
    read_measures();
    read_title();
    return std::move(spec_);
  }

 private:
  struct AxisDraft {
    GridAxis axis;  // values already set for { values = [...] }
    const toml::node* node;
    double from = 0.0, to = 0.0;
    std::int64_t n = 0;  // > 0: values still to come from linspace(from, to, n)
    std::int64_t size() const { return n > 0 ? n : std::ssize(axis.values); }
  };

  // --- messages ------------------------------------------------------------------------------

  // "file:line:column", or the --set argument a node came from, or the file alone.
  std::string where(const toml::node* at) const {
    if (at == nullptr || !at->source().path) return source_name_;
    const std::string& path = *at->source().path;
    if (path.starts_with(kSetPrefix)) return path;
    return fmt::format("{}:{}:{}", path, at->source().begin.line, at->source().begin.column);
  }

  [[noreturn]] void fail(const toml::node* at, std::string_view message) const {
    throw InputError(fmt::format("{}: {}", where(at), message));
  }

  [[noreturn]] void fail_type(const toml::node& node, std::string_view key,
                              std::string_view expected) const {
    fail(&node,
         fmt::format("{}: expected {}, got {} {}", key, expected, type_name(node), shown(node)));
  }

  [[noreturn]] void fail_value(const toml::node& node, std::string_view key,
                               std::string_view expected) const {
    fail(&node, fmt::format("{} = {}: expected {}", key, shown(node), expected));
  }

  // Every key of `table` must be in `allowed`; otherwise name it and suggest the likely one.
  void check_keys(const toml::table& table, std::string_view prefix, const Names& allowed) const {
    for (const auto& [key, node] : table) {
      if (contains(allowed, key.str())) continue;
      std::string hint = did_you_mean(key.str(), allowed, prefix);
      if (hint.empty()) hint = elsewhere_hint(key.str(), prefix);
      fail(&node,
           fmt::format("unknown key '{}'{}; valid {}: {}", dotted(prefix, key.str()), hint,
                       prefix.empty() ? "top-level keys" : fmt::format("keys in [{}]", prefix),
                       fmt::join(allowed, ", ")));
    }
  }

  // A key that belongs to another section ("gamma" under [integrator]) points there.
  std::string elsewhere_hint(std::string_view key, std::string_view prefix) const {
    for (const std::string& path : known_paths()) {
      const auto dot = path.rfind('.');
      if (path.substr(dot + 1) == key && path.substr(0, dot) != prefix)
        return fmt::format(" (did you mean '{}'?)", path);
    }
    return "";
  }

  Names known_paths() const {
    Names paths{"scene.name", "integrator.method", "integrator.h", "integrator.t_end"};
    if (scene_ == nullptr) return paths;
    for (const std::string& p : parameter_names(*scene_)) paths.push_back("scene." + p);
    for (const std::string& v : variable_names(*scene_)) paths.push_back("initial." + v);
    for (const std::string_view m : kMeasureNames) paths.push_back(fmt::format("measures.{}", m));
    return paths;
  }

  static Names top_level_keys() {
    Names keys{"title"};
    for (const std::string_view section : kSections) keys.emplace_back(section);
    return keys;
  }

  // --- typed access --------------------------------------------------------------------------

  double number(const toml::node& node, std::string_view key) const {
    double value = 0.0;
    if (const auto* i = node.as_integer())
      value = static_cast<double>(i->get());
    else if (const auto* f = node.as_floating_point())
      value = f->get();
    else
      fail_type(node, key, "a number");
    if (!std::isfinite(value)) fail_value(node, key, "a finite number");
    return value;
  }

  std::int64_t integer(const toml::node& node, std::string_view key) const {
    if (const auto* i = node.as_integer()) return i->get();
    fail_type(node, key, "an integer (a whole number without a decimal point)");
  }

  bool boolean(const toml::node& node, std::string_view key) const {
    if (const auto* b = node.as_boolean()) return b->get();
    fail_type(node, key, "true or false");
  }

  std::string string(const toml::node& node, std::string_view key) const {
    if (const auto* s = node.as_string()) {
      // TOML allows "\u0000"; HDF5 attributes and C strings would cut the text there.
      if (s->get().find('\0') != std::string::npos)
        fail(&node, fmt::format("{} contains a NUL character (\\u0000), which no attribute or "
                                "name can hold", key));
      return s->get();
    }
    fail_type(node, key, "a string (in quotes)");
  }

  const toml::table& table(const toml::node& node, std::string_view key) const {
    if (const auto* t = node.as_table()) return *t;
    fail_type(node, key, "a table");
  }

  const toml::array& array(const toml::node& node, std::string_view key) const {
    if (const auto* a = node.as_array()) return *a;
    fail_type(node, key, "an array [...]");
  }

  std::vector<double> numbers(const toml::node& node, std::string_view key) const {
    std::vector<double> values;
    const toml::array& items = array(node, key);
    for (std::size_t i = 0; i < items.size(); ++i)
      values.push_back(number(*items.get(i), fmt::format("{}[{}]", key, i)));
    return values;
  }

  // A top-level section; an absent one reads as empty so that every default applies.
  const toml::table& section(std::string_view name) const {
    static const toml::table empty;
    const toml::node* node = doc_.get(name);
    return node == nullptr ? empty : table(*node, name);
  }

  double number_or(const toml::table& t, std::string_view prefix, std::string_view key,
                   double fallback) const {
    const toml::node* node = t.get(key);
    return node == nullptr ? fallback : number(*node, dotted(prefix, key));
  }

  // --- [scene], [initial], title ------------------------------------------------------------

  void read_scene() {
    const Names scenes = names_of(scene_catalog());
    const toml::node* node = doc_.get("scene");
    if (node == nullptr)
      fail(nullptr,
           fmt::format("missing [scene] section with name = one of: {}", fmt::join(scenes, ", ")));
    const toml::table& t = table(*node, "scene");
    const toml::node* name = t.get("name");
    if (const toml::node* k = t.get("K")) {
      if (name != nullptr)
        fail(name, "[scene] has both name and K: write name for a built-in scene or K for your "
                   "own, not both");
      return read_custom_scene(t, *k);
    }
    if (name == nullptr)
      fail(node, fmt::format("scene.name is missing; valid scenes: {}", fmt::join(scenes, ", ")));
    spec_.scene = string(*name, "scene.name");
    scene_ = find_scene(spec_.scene);
    if (scene_ == nullptr)
      fail(name, fmt::format("unknown scene {}{}; valid scenes: {}", toml_string(spec_.scene),
                             did_you_mean(spec_.scene, scenes, ""), fmt::join(scenes, ", ")));
    Names allowed = parameter_names(*scene_);
    allowed.insert(allowed.begin(), "name");
    check_keys(t, "scene", allowed);
    for (const ParameterInfo& p : scene_->parameters)
      spec_.parameters[p.name] = number_or(t, "scene", p.name, p.paper_value);
  }

  // [scene] K = "...": every symbol of K that is not a variable is a parameter valued here, and
  // every other key must be a parameter of K (or label).
  void read_custom_scene(const toml::table& t, const toml::node& k) {
    const std::string text = string(k, "scene.K");
    const toml::node* label = t.get("label");
    const std::string name = label != nullptr ? string(*label, "scene.label") : "custom";
    if (name.empty()) fail(label, "scene.label is empty: expected a name for the output's scene");
    try {
      spec_.custom = make_custom_scene(text, name);
    } catch (const InputError& e) {
      fail(&k, e.what());
    }
    spec_.scene = name;
    scene_ = &spec_.custom->info;
    const Names parameters = parameter_names(*scene_);
    const Names state = variable_names(*scene_);  // q.., p.., z, lambda: K may use all but λ
    const Names positions_momenta(state.begin(), state.begin() + 2 * scene_->dof);
    for (const std::string& p : parameters)
      if (t.get(p) == nullptr)
        fail(&k, fmt::format("scene.K: symbol '{}' is neither a variable ({}, z, t, pi) nor a "
                             "parameter valued in [scene]: add {} = <number> under [scene]",
                             p, fmt::join(positions_momenta, ", "), p));
    for (const auto& [key, value] : t) {
      const std::string_view k_name = key.str();
      if (k_name == "K" || k_name == "label" || contains(parameters, std::string(k_name))) continue;
      fail(&value, fmt::format("scene.{} is not a symbol of K, so it would have no effect; K's "
                               "parameters: {}",
                               k_name, parameters.empty() ? "none" : fmt::format("{}", fmt::join(parameters, ", "))));
    }
    for (const std::string& p : parameters) {
      const double value = number(*t.get(p), "scene." + p);
      if (!std::isfinite(value)) fail_value(*t.get(p), "scene." + p, "a finite number");
      spec_.parameters[p] = value;
    }
  }

  void read_initial() {
    const toml::table& t = section("initial");
    check_keys(t, "initial", variable_names(*scene_));
    for (const VariableInfo& v : scene_->variables) {
      const double value = number_or(t, "initial", v.name, v.paper_value);
      if (must_be_positive(v.name) && !(value > 0.0))
        fail_value(*t.get(v.name), "initial." + v.name, "a number > 0");
      spec_.initial[v.name] = value;
    }
  }

  void read_title() {
    const toml::node* node = doc_.get("title");
    spec_.title = node != nullptr ? string(*node, "title")
                                  : fmt::format("{} with {}", spec_.scene, spec_.method);
  }

  // --- [integrator] --------------------------------------------------------------------------

  void read_integrator() {
    const toml::table& t = section("integrator");
    check_keys(t, "integrator", {"method", "h", "t_end", "t_start"});
    read_method(t);
    spec_.h = number_or(t, "integrator", "h", scene_->default_h);
    spec_.t_start = number_or(t, "integrator", "t_start", 0.0);
    spec_.t_end = number_or(t, "integrator", "t_end", spec_.t_start + scene_->default_t_end);
    if (!(spec_.h > 0.0)) fail_value(*t.get("h"), "integrator.h", "a number > 0");
    if (!std::isfinite(spec_.t_start))
      fail_value(*t.get("t_start"), "integrator.t_start", "a finite number");
    if (spec_.t_start == 0.0 && !(spec_.t_end > 0.0))
      fail_value(*t.get("t_end"), "integrator.t_end", "a number > 0");
    if (!(spec_.t_end > spec_.t_start))
      fail(t.get("t_end") != nullptr ? t.get("t_end") : t.get("t_start"),
           fmt::format("integrator.t_end = {} is not after integrator.t_start = {}", spec_.t_end,
                       spec_.t_start));
    spec_.steps = whole_steps(t.get("t_end") != nullptr ? t.get("t_end") : t.get("h"));
  }

  void read_method(const toml::table& t) {
    const toml::node* node = t.get("method");
    spec_.method =
        node != nullptr ? string(*node, "integrator.method") : std::string(kDefaultMethod);
    const MethodInfo* method = find_method(spec_.method);
    const Names methods = names_of(method_catalog());
    if (method == nullptr)
      fail(node, fmt::format("unknown method {}{}; valid methods: {}", toml_string(spec_.method),
                             did_you_mean(spec_.method, methods, ""), fmt::join(methods, ", ")));
    const Names missing = missing_split_parts(*method, scene_->split_parts);
    if (!missing.empty() && spec_.custom)
      fail(node, fmt::format("method {} needs K = sum of p_i^2/2 + V(q, t) + c(t)*z (or "
                             "c(t)*z^2), and scene.K does not split so; methods that work here: {}",
                             toml_string(spec_.method), fmt::join(usable_methods(), ", ")));
    if (!missing.empty())
      fail(node,
           fmt::format("method {} needs the exact sub-flow(s) {} that scene '{}' does not "
                       "offer (it offers: {}); methods that work here: {}",
                       toml_string(spec_.method), fmt::join(missing, ", "), scene_->name,
                       fmt::join(scene_->split_parts, ", "), fmt::join(usable_methods(), ", ")));
  }

  Names usable_methods() const {
    Names usable;
    for (const MethodInfo& m : method_catalog())
      if (missing_split_parts(m, scene_->split_parts).empty()) usable.push_back(m.name);
    return usable;
  }

  // How messages name the run's duration: plain t_end for the common start at 0.
  std::string duration_name() const {
    return spec_.t_start == 0.0 ? "t_end" : "t_end - t_start";
  }

  // (t_end − t_start) / h as a whole number of steps; `at` is the node to blame (t_end, else h,
  // else none).
  std::int64_t whole_steps(const toml::node* at) const {
    const double h = spec_.h, t0 = spec_.t_start, duration = spec_.t_end - t0;
    const double ratio = duration / h;
    const std::string span = duration_name();
    if (duration < h)
      fail(at, fmt::format("integrator.{} = {} is shorter than one step h = {}", span, duration, h));
    if (!(ratio <= kMaxSteps))
      fail(at, fmt::format("integrator.{} / h = {:.6g} steps: expected at most 2^53", span, ratio));
    const std::int64_t steps = std::llround(ratio);
    if (std::abs(static_cast<double>(steps) * h - duration) <= kStepTolerance * duration)
      return steps;
    const auto below = static_cast<std::int64_t>(std::floor(ratio));
    fail(at, fmt::format("integrator.{} = {} is not a whole number of steps of h = {} "
                         "({} / h = {:.12g}); nearest valid t_end: {:.15g} ({} steps) or "
                         "{:.15g} ({} steps)",
                         span, duration, h, span, ratio, t0 + static_cast<double>(below) * h,
                         below, t0 + static_cast<double>(below + 1) * h, below + 1));
  }

  // --- [grid] --------------------------------------------------------------------------------

  void read_grid() {
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
      spec_.axes.push_back(std::move(draft.axis));
    }
  }

  // Scene parameters by name, initial values as <variable>_0.
  Names axis_names() const {
    Names names = parameter_names(*scene_);
    names.push_back("h");  // stability and accuracy maps over the step size
    for (const std::string& v : variable_names(*scene_)) names.push_back(v + "_0");
    return names;
  }

  AxisDraft read_axis(const std::string& name, const toml::node& node) const {
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

  void check_grid_size(const std::vector<AxisDraft>& drafts) const {
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
    // Before linspace fills anything: the coordinates, and at least one 8-byte result per point
    // (check_resources in sweep.cpp refines this once the measures are known).
    double bytes = static_cast<double>(points);
    for (const AxisDraft& draft : drafts) bytes += static_cast<double>(draft.size());
    bytes *= sizeof(double);
    if (const MemoryBudget budget = memory_budget(); bytes > 0.8 * budget.bytes)
      fail(doc_.get("grid"),
           fmt::format("the grid has {} points and needs at least {:.3g} GiB of memory, but {:.3g} "
                       "GiB is available ({}); use a coarser grid or split the sweep",
                       points, bytes / 1073741824.0, budget.bytes / 1073741824.0, budget.source));
  }

  void check_axis_values(const AxisDraft& draft) const {
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

  // A grid over h integrates each h as its own slice: it must be the first axis (slices are
  // then contiguous), and every h must divide t_end into whole steps.
  void check_step_size(const AxisDraft& draft, double h) const {
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

  // --- [measures] ----------------------------------------------------------------------------

  void read_measures() {
    const toml::node* node = doc_.get("measures");
    if (node == nullptr) {
      spec_.measures.final_state = FinalStateMeasure{variable_names(*scene_)};
      return;
    }
    const toml::table& t = table(*node, "measures");
    check_keys(t, "measures", Names(std::begin(kMeasureNames), std::end(kMeasureNames)));
    read_final_state(t);
    read_trajectory(t);
    read_basin(t);
    read_sync(t);
    const Measures& m = spec_.measures;
    if (!m.final_state && !m.trajectory && !m.basin && !m.sync)
      fail(node, fmt::format("[measures] requests nothing; scene '{}' supports: {}", scene_->name,
                             fmt::join(scene_->measures, ", ")));
  }

  // The settings of one measure: nullptr when absent or false; `true` reads as empty settings.
  const toml::table* measure_settings(const toml::table& measures, std::string_view name,
                                      const Names& keys) const {
    static const toml::table defaults;
    const toml::node* node = measures.get(name);
    if (node == nullptr) return nullptr;
    const std::string key = fmt::format("measures.{}", name);
    const toml::table* settings = &defaults;
    if (const auto* b = node->as_boolean()) {
      if (!b->get()) return nullptr;
    } else if (node->is_table()) {
      settings = node->as_table();
    } else {
      fail_type(*node, key,
                fmt::format("true, false or a table {{ {} = ... }}", fmt::join(keys, ", ")));
    }
    if (!contains(scene_->measures, name))
      fail(node, fmt::format("{}: scene '{}' does not support '{}'; it supports: {}", key,
                             scene_->name, name, fmt::join(scene_->measures, ", ")));
    check_keys(*settings, key, keys);
    return settings;
  }

  void read_final_state(const toml::table& measures) {
    const toml::table* t = measure_settings(measures, "final_state", {"vars"});
    if (t == nullptr) return;
    const Names all = variable_names(*scene_);
    const toml::node* vars = t->get("vars");
    if (vars == nullptr) {
      spec_.measures.final_state = FinalStateMeasure{all};
      return;
    }
    const toml::array& list = array(*vars, "measures.final_state.vars");
    if (list.empty())
      fail_value(*vars, "measures.final_state.vars",
                 "at least one variable (or final_state = false)");
    Names chosen;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string key = fmt::format("measures.final_state.vars[{}]", i);
      const std::string var = string(*list.get(i), key);
      if (!contains(all, var))
        fail_value(*list.get(i), key,
                   fmt::format("a variable of scene '{}': {}{}", scene_->name, fmt::join(all, ", "),
                               did_you_mean(var, all, "")));
      if (contains(chosen, var)) fail_value(*list.get(i), key, "each variable once");
      chosen.push_back(var);
    }
    Names in_scene_order;
    for (const std::string& var : all)
      if (contains(chosen, var)) in_scene_order.push_back(var);
    spec_.measures.final_state = FinalStateMeasure{in_scene_order};
  }

  void read_trajectory(const toml::table& measures) {
    const toml::table* t = measure_settings(measures, "trajectory", {"every"});
    if (t == nullptr) return;
    TrajectoryMeasure trajectory;
    if (const toml::node* every = t->get("every")) {
      trajectory.every = integer(*every, "measures.trajectory.every");
      if (trajectory.every < 1)
        fail_value(*every, "measures.trajectory.every", "an integer >= 1 (steps between samples)");
    }
    if (!spec_.axes.empty() && spec_.axes.front().is_step_size)
      fail(measures.get("trajectory"), "measures.trajectory cannot be combined with a grid over h "
                                       "(the time axis would differ from one h to the next)");
    spec_.measures.trajectory = trajectory;
  }

  void read_basin(const toml::table& measures) {
    const toml::table* t = measure_settings(
        measures, "basin",
        {"early_stop", "period", "tolerance", "dwell", "max_period", "exact_trap", "angles"});
    if (t == nullptr) return;
    BasinMeasure basin;
    if (const toml::node* early_stop = t->get("early_stop"))
      basin.early_stop = boolean(*early_stop, "measures.basin.early_stop");
    if (const toml::node* exact_trap = t->get("exact_trap"))
      basin.exact_trap = boolean(*exact_trap, "measures.basin.exact_trap");
    if (const toml::node* period = t->get("period")) read_basin_period(*period, basin);
    if (const toml::node* tolerance = t->get("tolerance")) {
      basin.tolerance = number(*tolerance, "measures.basin.tolerance");
      if (!(basin.tolerance > 0.0))
        fail_value(*tolerance, "measures.basin.tolerance",
                   "a distance > 0 (max norm over q and p)");
    }
    basin.dwell = basin.period ? BasinMeasure::kDefaultDwellPeriods * *basin.period
                               : BasinMeasure::kDefaultDwell;
    if (const toml::node* dwell = t->get("dwell")) {
      basin.dwell = number(*dwell, "measures.basin.dwell");
      if (!(basin.dwell > 0.0))
        fail_value(*dwell, "measures.basin.dwell",
                   "a time > 0 (how long a lane must stay near its attractor)");
    }
    if (basin.period) basin.max_period = BasinMeasure::kDefaultMaxPeriod;
    if (const toml::node* max_period = t->get("max_period")) {
      const std::int64_t m = integer(*max_period, "measures.basin.max_period");
      if (!basin.period && m != 1)
        fail(max_period, "measures.basin.max_period: cycles are looked for on the stroboscopic "
                         "map only; give measures.basin.period (the forcing period) too");
      if (m < 1 || m > BasinMeasure::kMaxPeriodLimit)
        fail_value(*max_period, "measures.basin.max_period",
                   fmt::format("an integer from 1 to {}", BasinMeasure::kMaxPeriodLimit));
      basin.max_period = static_cast<int>(m);
    }
    if (const toml::node* angles = t->get("angles")) {
      const toml::table& list = table(*angles, "measures.basin.angles");
      Names phase_space;
      for (const auto& v : scene_->variables)
        if (v.name != "z" && v.name != "lambda") phase_space.push_back(v.name);
      for (const auto& [name, value] : list) {
        const std::string key = fmt::format("measures.basin.angles.{}", name.str());
        if (!contains(phase_space, std::string(name.str())))
          fail(&value, fmt::format("{}: '{}' is not a position or momentum of scene '{}' ({}){}",
                                   key, name.str(), scene_->name, fmt::join(phase_space, ", "),
                                   did_you_mean(std::string(name.str()), phase_space, "")));
        const double angle_period = number(value, key);
        if (!(angle_period > 0.0))
          fail_value(value, key, "the variable's period > 0 (e.g. 6.283185307179586)");
        basin.angles[std::string(name.str())] = angle_period;
      }
    }
    spec_.measures.basin = basin;
  }

  // The stroboscopic map samples every period/h steps: a whole number for every step size.
  void read_basin_period(const toml::node& node, BasinMeasure& basin) {
    const std::string key = "measures.basin.period";
    const double period = number(node, key);
    if (!(period > 0.0)) fail_value(node, key, "the forcing period > 0");
    std::vector<double> hs{spec_.h};
    if (!spec_.axes.empty() && spec_.axes.front().is_step_size) hs = spec_.axes.front().values;
    for (double h : hs) {
      const double ratio = period / h;
      const auto steps = std::llround(ratio);
      if (steps < 1 || std::abs(static_cast<double>(steps) * h - period) > kStepTolerance * period)
        fail(&node, fmt::format("{} = {}: the stroboscopic map needs a whole number of steps per "
                                "period, but period / h = {:.12g} at h = {}; choose h = period / N",
                                key, period, ratio, h));
    }
    basin.period = period;
  }

  void read_sync(const toml::table& measures) {
    const toml::table* t = measure_settings(measures, "sync", {"window", "dof", "omega"});
    if (t == nullptr) return;
    SyncMeasure sync;  // the second half of the run by default
    sync.window_from = spec_.t_start + (spec_.t_end - spec_.t_start) / 2.0;
    sync.window_to = spec_.t_end;
    read_sync_pair(*t, sync);
    if (const toml::node* window = t->get("window")) {
      const std::string key = "measures.sync.window";
      const std::vector<double> ends = numbers(*window, key);
      if (ends.size() != 2) fail_value(*window, key, "two numbers [from, to]");
      if (!(spec_.t_start <= ends[0] && ends[0] < ends[1] && ends[1] <= spec_.t_end))
        fail_value(*window, key,
                   fmt::format("[from, to] with {} <= from < to <= t_end = {}",
                               spec_.t_start == 0.0 ? std::string("0")
                                                    : fmt::format("t_start = {}", spec_.t_start),
                               spec_.t_end));
      if (ends[1] - ends[0] < spec_.h)
        fail_value(*window, key, fmt::format("a window at least one step h = {} long", spec_.h));
      sync.window_from = ends[0], sync.window_to = ends[1];
    }
    spec_.measures.sync = sync;
  }

  // Which two degrees of freedom, and the frequencies that scale their momenta.
  void read_sync_pair(const toml::table& t, SyncMeasure& sync) {
    if (const toml::node* dof = t.get("dof")) {
      const std::string key = "measures.sync.dof";
      const toml::array& list = array(*dof, key);
      const int n = scene_->dof;
      if (list.size() != 2) fail_value(*dof, key, "two degrees of freedom [i, j], counted from 1");
      for (std::size_t k = 0; k < 2; ++k) {
        const std::int64_t i = integer(*list.get(k), fmt::format("{}[{}]", key, k));
        if (i < 1 || i > n)
          fail_value(*list.get(k), fmt::format("{}[{}]", key, k),
                     fmt::format("a degree of freedom of scene '{}', from 1 to {}", scene_->name, n));
        sync.dof[k] = static_cast<int>(i - 1);
      }
      if (sync.dof[0] == sync.dof[1]) fail_value(*dof, key, "two different degrees of freedom");
    }
    if (const toml::node* omega = t.get("omega")) {
      const std::string key = "measures.sync.omega";
      const std::vector<double> w = numbers(*omega, key);
      if (w.size() != 2 || !(w[0] > 0.0) || !(w[1] > 0.0))
        fail_value(*omega, key, "two frequencies > 0 [omega_i, omega_j] that scale p_i and p_j");
      sync.omega = std::array<double, 2>{w[0], w[1]};
    }
  }

  const toml::table& doc_;
  std::string source_name_;
  Names grid_order_;
  const SceneInfo* scene_ = nullptr;
  RunSpec spec_;
};

// ---------------------------------------------------------------------------------------------
// Parsing, --set overrides, grid order

toml::table parse_document(std::string_view text, std::string_view source_name) {
  try {
    return toml::parse(text, std::string(source_name));
  } catch (const toml::parse_error& error) {
    throw InputError(fmt::format("{}:{}:{}: malformed TOML: {}", source_name,
                                 error.source().begin.line, error.source().begin.column,
                                 error.description()));
  }
}

// toml::table iterates in key order, but the first grid axis varies slowest: recover file order.
Names keys_in_source_order(const toml::node* node) {
  std::vector<std::pair<toml::source_position, std::string>> keyed;
  if (const toml::table* t = node != nullptr ? node->as_table() : nullptr)
    for (const auto& [key, value] : *t) keyed.emplace_back(value.source().begin, key.str());
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  Names keys;
  for (auto& entry : keyed) keys.push_back(std::move(entry.second));
  return keys;
}

struct Override {
  std::string arg;     // as given, for messages
  Names path;          // the dotted key, split
  toml::table parsed;  // "KEY = VALUE" parsed: tables it creates carry the --set origin
};

std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  return std::string(text.substr(first, text.find_last_not_of(" \t") - first + 1));
}

Names split_key(const std::string& key, const std::string& arg) {
  Names path;
  std::size_t begin = 0;
  while (true) {
    const std::size_t dot = key.find('.', begin);
    path.push_back(key.substr(begin, dot - begin));
    if (!is_bare_key(path.back()))
      throw InputError(
          fmt::format("--set {}: '{}' is not a dotted key of plain names "
                      "(like integrator.h or grid.q_0.n)",
                      arg, key));
    if (dot == std::string::npos) return path;
    begin = dot + 1;
  }
}

// A word such as double_well: no TOML value, and clearly meant as a string whose quotes the
// shell removed.
bool is_bare_word(std::string_view value) {
  return is_bare_key(value) && std::isalpha(static_cast<unsigned char>(value.front()));
}

// "KEY = VALUE" must hold nothing but KEY: VALUE could smuggle in more keys ("1\nx = 2").
void check_single_value(const Override& edit) {
  const toml::table* level = &edit.parsed;
  for (const std::string& key : edit.path) {
    if (level->size() != 1)
      throw InputError(fmt::format("--set {}: the value must be a single TOML value", edit.arg));
    level = level->get(key)->as_table();  // nullptr at the value itself, ending the walk
    if (level == nullptr) return;
  }
}

Override parse_override(const std::string& arg) {
  const std::size_t eq = arg.find('=');
  if (eq == std::string::npos)
    throw InputError(
        fmt::format("--set {}: expected KEY=VALUE, e.g. --set integrator.h=0.005", arg));
  const std::string key = trimmed(std::string_view(arg).substr(0, eq));
  const std::string value = trimmed(std::string_view(arg).substr(eq + 1));
  if (key.empty()) throw InputError(fmt::format("--set {}: empty key before '='", arg));
  if (value.empty()) throw InputError(fmt::format("--set {}: empty value after '='", arg));
  Override result{arg, split_key(key, arg), {}};
  const std::string origin = std::string(kSetPrefix) + arg;
  try {
    result.parsed = toml::parse(key + " = " + value, origin);
  } catch (const toml::parse_error& error) {
    if (!is_bare_word(value))
      throw InputError(
          fmt::format("--set {}: {} is not a TOML value ({}); strings need quotes, "
                      "e.g. --set 'scene.name=\"double_well\"'",
                      arg, value, error.description()));
    result.parsed = toml::parse(key + " = " + toml_string(value), origin);
  }
  check_single_value(result);
  return result;
}

// Moving (not copying) keeps the node's source region, so messages can name the --set argument.
void move_into(toml::table& table, const std::string& key, toml::node& node) {
  node.visit([&](auto& value) { table.insert_or_assign(key, std::move(value)); });
}

void apply_override(toml::table& doc, Override& edit) {
  toml::table* target = &doc;
  toml::table* incoming = &edit.parsed;
  for (std::size_t i = 0; i < edit.path.size(); ++i) {
    const std::string& key = edit.path[i];
    toml::node* node = incoming->get(key);
    toml::node* existing = target->get(key);
    if (existing == nullptr || i + 1 == edit.path.size()) {
      move_into(*target, key, *node);
      return;
    }
    if (!existing->is_table())
      throw InputError(fmt::format(
          "--set {0}: '{1}' is {2} in the spec, not a table; set it whole (--set {1}=...)",
          edit.arg, fmt::join(edit.path.begin(), edit.path.begin() + i + 1, "."),
          type_name(*existing)));
    target = existing->as_table();
    incoming = node->as_table();
  }
}

// An axis keeps its place when --set changes it; a new axis comes last.
void update_grid_order(Names& order, const Names& path, const toml::table& doc) {
  if (path.front() != "grid") return;
  if (path.size() == 1) {
    order = keys_in_source_order(doc.get("grid"));
  } else if (!contains(order, path[1])) {
    order.push_back(path[1]);
  }
}

// ---------------------------------------------------------------------------------------------
// spec_text: the document after --set, sections in a fixed order, grid axes in grid order.

std::string to_toml(const toml::table& doc, const Names& grid_order) {
  std::string text;
  if (const toml::node* title = doc.get("title")) text += "title = " + inline_toml(*title) + "\n";
  for (const std::string_view name : kSections) {
    const toml::table* section = doc[name].as_table();
    if (section == nullptr) continue;
    text += fmt::format("{}[{}]\n", text.empty() ? "" : "\n", name);
    const Names keys = name == "grid" ? grid_order : keys_in_written_order(*section);
    for (const std::string& key : keys)
      text += fmt::format("{} = {}\n", key_text(key), inline_toml(*section->get(key)));
  }
  return text;
}

}  // namespace

std::string read_spec_file(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    throw InputError(fmt::format("cannot read spec file '{}': it is a directory", path));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("cannot read spec file '{}': {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("cannot read spec file '{}': read error", path));
  return text.str();
}

std::vector<double> linspace(double from, double to, std::int64_t n) {
  if (n <= 0) return {};
  // numpy 1.24 function_base.linspace, step by step: y = arange(n) * step + from, with
  // y = arange(n) / div * delta where step underflows to 0, and the last point set to `to`.
  std::vector<double> y(static_cast<std::size_t>(n));
  const double delta = to - from;
  const std::int64_t div = n - 1;
  if (div == 0) {
    y[0] = 0.0 * delta + from;
    return y;
  }
  const double step = delta / static_cast<double>(div);
  for (std::int64_t i = 0; i < n; ++i) {
    const double index = static_cast<double>(i);
    const double offset = step == 0.0 ? index / static_cast<double>(div) * delta : index * step;
    y[static_cast<std::size_t>(i)] = offset + from;
  }
  y.back() = to;
  return y;
}

RunSpec parse_run_spec(std::string_view toml_text, const std::vector<std::string>& overrides,
                       std::string_view source_name) {
  toml::table doc = parse_document(toml_text, source_name);
  Names grid_order = keys_in_source_order(doc.get("grid"));
  for (const std::string& arg : overrides) {
    Override edit = parse_override(arg);
    apply_override(doc, edit);
    update_grid_order(grid_order, edit.path, doc);
  }
  RunSpec spec = SpecReader(doc, source_name, grid_order).read();
  spec.spec_text = to_toml(doc, grid_order);
  return spec;
}

RunSpec load_run_spec(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_run_spec(read_spec_file(path), overrides, path);
}

std::int64_t RunSpec::grid_points() const {
  std::int64_t points = 1;
  for (const GridAxis& axis : axes) points *= std::ssize(axis.values);
  return points;
}

}  // namespace cs
