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

// How a basin map numbers the attractors it found (engine/attractor_table.cpp).
struct LabelRule {
  enum Kind {
    block_order,  // 1, 2, … in the order the blocks found them (any scene)
    sign_of_q1    // −1 and +1 by the sign of the attractor's first position (two wells)
  } kind = block_order;
  std::string negative, positive;  // sign_of_q1: the names of labels −1 and +1
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
  LabelRule label_rule{};
};

const std::vector<SceneInfo>& scene_catalog();

// The built-in scenes' entries, generated from physics/scenes.toml (scene_catalog_data.cpp).
std::vector<SceneInfo> builtin_scene_infos();

// nullptr when no scene has that name.
const SceneInfo* find_scene(std::string_view name);

}  // namespace cs
