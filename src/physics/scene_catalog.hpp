// What the edge of the program (spec validation, `contactsweep scenes`, HDF5 attributes) needs
// to know about a scene at run time. A built-in scene has one source, its entry in
// physics/scenes.toml: the build generates from it both this description
// (scene_catalog_data.cpp) and the scene's header with K (formula/scene_catalog_gen.cpp).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cs {

struct ParameterInfo {
  std::string name;
  double paper_value;  // the default: the value printed in the paper
  std::string description;
};

struct VariableInfo {
  std::string name;          // as written in [initial] and in dataset names: q, p1, z, lambda
  double paper_value;        // default initial value
  std::string description;
};

// How the attractor table labels a scene's attractors (engine/label_rule.hpp). `numbered`: 1..n
// in the table's order (period, then point), for any scene. `sign_of_q1`: −1 and +1 by the sign
// of the attractor's first position, for a scene known to have one attractor on either side of
// q1 = 0; `negative` and `positive` name them in the file's flag_meanings.
struct LabelRule {
  enum class Kind { numbered, sign_of_q1 };
  Kind kind = Kind::numbered;
  std::string negative, positive;
};

struct SceneInfo {
  std::string name;          // spec name: damped_oscillator, ...
  std::string paper_label;   // "A".."D"
  std::string hamiltonian;   // K written out, for `contactsweep scenes` and the file's attributes
  int dof;                   // degrees of freedom: number of (q, p) pairs
  std::vector<ParameterInfo> parameters;
  std::vector<VariableInfo> variables;   // q..., p..., z, lambda
  std::vector<std::string> measures;     // measures this scene supports
  std::vector<std::string> split_parts;  // exact sub-flows it offers to splitting methods
  bool z_feeds_back;         // does z enter the (q, p) dynamics?
  double default_h;
  double default_t_end;
  LabelRule label_rule{};    // how its basins are labelled
  // A built-in scene's generated header (physics/<name>.hpp) and its struct: the run-time
  // kernel of a run with measures as formulas is compiled with it (parallel/sweep.cpp).
  std::string kernel_struct = {};
  std::string kernel_header = {};
};

const std::vector<SceneInfo>& scene_catalog();

// The built-in scenes' entries, generated from physics/scenes.toml (scene_catalog_data.cpp).
std::vector<SceneInfo> builtin_scene_infos();

// nullptr when no scene has that name.
const SceneInfo* find_scene(std::string_view name);

}  // namespace cs
