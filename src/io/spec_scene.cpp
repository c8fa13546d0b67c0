// [scene] (a built-in scene by name, or K written in the spec), [initial] and the title.
#include "io/spec_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <string>

#include "formula/custom_scene.hpp"
#include "io/spec_suggestions.hpp"
#include "io/spec_text.hpp"

namespace cs::spec {

void SpecReader::read_scene() {
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

void SpecReader::read_custom_scene(const toml::table& t, const toml::node& k) {
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
  // A parameter swept by a grid axis takes its values from the axis (read_grid fills in
  // spec_.parameters then), so it needs no value here.
  for (const std::string& p : parameters)
    if (t.get(p) == nullptr && !contains(grid_order_, p))
      fail(&k, fmt::format("scene.K: symbol '{}' is neither a variable ({}, z, t, pi) nor a "
                           "parameter valued in [scene]: add {} = <number> under [scene], or "
                           "sweep it as a grid axis{}",
                           p, fmt::join(positions_momenta, ", "), p,
                           contact_variable_hint(p, {"z"}, "")));
  for (const auto& [key, value] : t) {
    const std::string_view k_name = key.str();
    if (k_name == "K" || k_name == "label" || contains(parameters, std::string(k_name))) continue;
    fail(&value, fmt::format("scene.{} is not a symbol of K, so it would have no effect; K's "
                             "parameters: {}",
                             k_name, parameters.empty() ? "none" : fmt::format("{}", fmt::join(parameters, ", "))));
  }
  for (const std::string& p : parameters) {
    if (t.get(p) == nullptr) continue;  // swept: see above
    const double value = number(*t.get(p), "scene." + p);
    if (!std::isfinite(value)) fail_value(*t.get(p), "scene." + p, "a finite number");
    spec_.parameters[p] = value;
  }
}

void SpecReader::read_initial() {
  const toml::table& t = section("initial");
  check_keys(t, "initial", variable_names(*scene_));
  for (const VariableInfo& v : scene_->variables) {
    const double value = number_or(t, "initial", v.name, v.paper_value);
    if (must_be_positive(v.name) && !(value > 0.0))
      fail_value(*t.get(v.name), "initial." + v.name, "a number > 0");
    spec_.initial[v.name] = value;
  }
}

void SpecReader::read_title() {
  const toml::node* node = doc_.get("title");
  spec_.title = node != nullptr ? string(*node, "title")
                                : fmt::format("{} with {}", spec_.scene, spec_.method);
}

}  // namespace cs::spec
