// Build-time generator of the built-in scenes from their one source, src/physics/scenes.toml:
//   scene_catalog_gen SCENES_TOML OUTPUT_DIR
// writes OUTPUT_DIR/physics/<name>.hpp (each scene's header, by the code generator a spec's
// scene.K goes through), OUTPUT_DIR/physics/builtin_scenes.hpp (the list the engine is compiled
// for) and OUTPUT_DIR/physics/scene_catalog_data.cpp (the run-time SceneInfo of each). Every
// file is written (and so dated) on each run: the build runs it only when the data file or the
// generator changed, and a file left older than its source would make it run again every time.
// Any error in the data file names the scene and the key, exits 1 and writes nothing.
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "formula/k_formula.hpp"

namespace {

struct Named {
  std::string name, description;
  double value = 0.0;
};

struct Entry {
  std::string name, type, paper_label, K;
  std::vector<Named> parameters, variables;
  std::vector<std::string> natural_frequencies;
  std::string label_rule = "numbered", negative_label, positive_label;
  double default_h = 0.0, default_t_end = 0.0;
  cs::KFormula formula;
  std::string header;  // generated (physics/<name>.hpp)
};

[[noreturn]] void fail(const std::string& where, const std::string& message) {
  throw std::runtime_error(where + ": " + message);
}


template <class T>
T required(const toml::table& t, const std::string& key, const std::string& where) {
  auto v = t[key].value<T>();
  if (!v) fail(where, "'" + key + "' is missing or has the wrong type");
  return *v;
}

std::vector<Named> named_list(const toml::table& t, const std::string& key, const std::string& where) {
  const toml::array* a = t[key].as_array();
  if (a == nullptr) fail(where, "'" + key + "' must be an array of {name, value, description}");
  std::vector<Named> out;
  for (const auto& item : *a) {
    const toml::table* e = item.as_table();
    if (e == nullptr) fail(where, "each entry of '" + key + "' must be a table");
    const std::string at = where + "." + key;
    out.push_back({required<std::string>(*e, "name", at), required<std::string>(*e, "description", at),
                   required<double>(*e, "value", at)});
  }
  return out;
}

Entry read_entry(const toml::table& t) {
  Entry e;
  e.name = required<std::string>(t, "name", "scene");
  const std::string where = "scene " + e.name;
  for (char c : e.name)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'))
      fail(where, "a scene name is lower case letters, digits and '_'");
  e.type = cs::scene_struct_name(e.name);
  e.paper_label = required<std::string>(t, "paper_label", where);
  e.K = required<std::string>(t, "K", where);
  e.parameters = named_list(t, "parameters", where);
  e.variables = named_list(t, "variables", where);
  e.default_h = required<double>(t, "default_h", where);
  e.default_t_end = required<double>(t, "default_t_end", where);
  if (const toml::array* f = t["natural_frequencies"].as_array())
    for (const auto& item : *f) {
      auto text = item.value<std::string>();
      if (!text) fail(where, "natural_frequencies holds formulas (strings)");
      e.natural_frequencies.push_back(*text);
    }
  if (const toml::table* rule = t["label_rule"].as_table()) {
    e.label_rule = required<std::string>(*rule, "rule", where + ".label_rule");
    if (e.label_rule == "sign_of_q1") {
      e.negative_label = required<std::string>(*rule, "negative", where + ".label_rule");
      e.positive_label = required<std::string>(*rule, "positive", where + ".label_rule");
    } else if (e.label_rule != "numbered") {
      fail(where, "label_rule.rule is \"numbered\" or \"sign_of_q1\", not \"" + e.label_rule + "\"");
    }
  }
  try {
    e.formula = cs::parse_k(e.K);
    std::vector<std::string> order;
    for (const Named& p : e.parameters) order.push_back(p.name);
    cs::order_parameters(e.formula, order);
  } catch (const std::exception& x) {
    fail(where, x.what());
  }
  // The state variables, in the kernel's order: q…, p…, z, lambda.
  std::vector<std::string> expected = e.formula.positions;
  expected.insert(expected.end(), e.formula.momenta.begin(), e.formula.momenta.end());
  expected.insert(expected.end(), {"z", "lambda"});
  std::vector<std::string> given;
  for (const Named& v : e.variables) given.push_back(v.name);
  std::vector<std::string> sorted_given = given, sorted_expected = expected;
  std::sort(sorted_given.begin(), sorted_given.end());
  std::sort(sorted_expected.begin(), sorted_expected.end());
  if (sorted_given != sorted_expected)
    fail(where, "variables must be exactly those of K, z and lambda");
  return e;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The shortest text that reads back as x, as a double literal.
std::string number(double x) {
  char buffer[64];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
  std::string s(buffer, end);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string list(const std::vector<std::string>& items) {
  std::string out = "{";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + quoted(items[i]);
  return out + "}";
}

std::string named_entries(const std::vector<Named>& items, const std::vector<std::string>& order) {
  std::string out;
  for (const std::string& name : order)
    for (const Named& v : items)
      if (v.name == name)
        out += "\n           {" + quoted(v.name) + ", " + number(v.value) + ", " + quoted(v.description) + "},";
  return "{" + out + "}";
}

std::string catalog_source(const std::vector<Entry>& entries) {
  std::ostringstream s;
  s << "// Generated by scene_catalog_gen from src/physics/scenes.toml. Do not edit.\n"
    << "#include \"physics/scene_catalog.hpp\"\n\nnamespace cs {\n\n"
    << "std::vector<SceneInfo> builtin_scene_infos() {\n  std::vector<SceneInfo> scenes;\n";
  for (const Entry& e : entries) {
    const cs::KTraits& tr = e.formula.traits;
    std::vector<std::string> measures{"final_state", "trajectory", "basin", "lyapunov"};
    if (tr.dof >= 2) measures.push_back("sync");
    std::vector<std::string> split;
    if (tr.z_part)
      split = {"kinetic", "potential", *tr.z_part == cs::ZPart::linear ? "z_linear" : "z_quadratic"};
    std::vector<std::string> parameter_order;
    for (const Named& p : e.parameters) parameter_order.push_back(p.name);
    // Variables in the kernel's order: q…, p…, z, lambda (the grid fills the state in it).
    std::vector<std::string> variable_order = e.formula.positions;
    variable_order.insert(variable_order.end(), e.formula.momenta.begin(), e.formula.momenta.end());
    variable_order.insert(variable_order.end(), {"z", "lambda"});
    s << "  scenes.push_back({\n"
      << "      .name = " << quoted(e.name) << ",\n"
      << "      .paper_label = " << quoted(e.paper_label) << ",\n"
      << "      .hamiltonian = " << quoted("K = " + e.K) << ",\n"
      << "      .dof = " << tr.dof << ",\n"
      << "      .parameters = " << named_entries(e.parameters, parameter_order) << ",\n"
      << "      .variables = " << named_entries(e.variables, variable_order) << ",\n"
      << "      .measures = " << list(measures) << ",\n"
      << "      .split_parts = " << list(split) << ",\n"
      << "      .z_feeds_back = " << (tr.z_feeds_back ? "true" : "false") << ",\n"
      << "      .default_h = " << number(e.default_h) << ",\n"
      << "      .default_t_end = " << number(e.default_t_end) << ",\n";
    if (e.label_rule == "sign_of_q1")
      s << "      .label_rule = {LabelRule::Kind::sign_of_q1, " << quoted(e.negative_label) << ", "
        << quoted(e.positive_label) << "},\n";
    s << "  });\n";
  }
  s << "  return scenes;\n}\n\n}  // namespace cs\n";
  return s.str();
}

std::string list_header(const std::vector<Entry>& entries) {
  std::ostringstream s;
  s << "// Generated by scene_catalog_gen from src/physics/scenes.toml. Do not edit.\n"
    << "// The built-in scenes the program is compiled for, in the catalog's order.\n"
    << "#pragma once\n\n";
  for (const Entry& e : entries) s << "#include \"physics/" << e.name << ".hpp\"\n";
  s << "\nnamespace cs {\n\ntemplate <class... Scenes>\nstruct SceneList {};\n\n"
    << "using BuiltinScenes = SceneList<";
  for (std::size_t i = 0; i < entries.size(); ++i) s << (i ? ", " : "") << entries[i].type;
  s << ">;\n\n}  // namespace cs\n";
  return s.str();
}

void write(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: scene_catalog_gen SCENES_TOML OUTPUT_DIR\n";
    return 2;
  }
  try {
    const toml::table data = toml::parse_file(argv[1]);
    const toml::array* scenes = data["scene"].as_array();
    if (scenes == nullptr || scenes->empty()) fail(argv[1], "no [[scene]] entries");
    std::vector<Entry> entries;
    for (const auto& item : *scenes) entries.push_back(read_entry(*item.as_table()));
    // Everything is generated before anything is written: a bad entry leaves no file behind.
    std::vector<std::pair<std::string, std::string>> files;  // name, text
    for (Entry& e : entries) {
      cs::SceneHeaderExtras extras;
      extras.source_note = "Built-in scene " + e.name + " (the paper's scene " + e.paper_label +
                           "), generated from src/physics/scenes.toml by scene_catalog_gen. "
                           "Do not edit.";
      extras.name = e.name;
      extras.natural_frequencies = e.natural_frequencies;
      try {
        e.header = cs::scene_header(e.formula, e.type, extras);
        files.emplace_back(e.name + ".hpp", e.header);
      } catch (const std::exception& x) {
        fail("scene " + e.name, x.what());
      }
    }
    files.emplace_back("builtin_scenes.hpp", list_header(entries));
    files.emplace_back("scene_catalog_data.cpp", catalog_source(entries));
    const std::filesystem::path out = std::filesystem::path(argv[2]) / "physics";
    for (const auto& [name, text] : files) write(out / name, text);
  } catch (const toml::parse_error& e) {
    std::cerr << "scene_catalog_gen: " << argv[1] << ": " << e.description() << " (line "
              << e.source().begin.line << ")\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "scene_catalog_gen: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
