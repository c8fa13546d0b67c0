// Measures as formulas (measure_formulas.hpp): each formula through K's parser and code
// generator, conditions split into comparisons here, and the generated struct.
#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>
#include <vector>

#include "formula/k_tree.hpp"
#include "formula/measure_formulas.hpp"

namespace cs {
namespace {

using namespace k_formula;

[[noreturn]] void refuse(const std::string& key, const std::string& message) {
  throw InputError(key + ": " + message);
}

// A formula as messages quote it: without the blanks around it.
std::string shown(const std::string& text) {
  const auto b = text.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return "'" + text.substr(b, text.find_last_not_of(" \t\r\n") + 1 - b) + "'";
}

std::vector<std::string> names_of_state(const SceneInfo& scene) {
  std::vector<std::string> names;
  for (const auto& v : scene.variables) names.push_back(v.name);
  names.push_back("t");
  return names;
}

std::vector<std::string> parameter_names(const SceneInfo& scene) {
  std::vector<std::string> names;
  for (const auto& p : scene.parameters) names.push_back(p.name);
  return names;
}

// K's parser on a formula; its messages ("scene.K: ...") reworded for `key`. `column_offset`
// spaces in front keep the columns of a part of a condition those of the whole text.
Parsed parse_formula(const std::string& key, const std::string& text, std::size_t column_offset) {
  std::string padded = std::string(column_offset, ' ') + text;
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    refuse(key, "an empty formula" + std::string(column_offset ? " at column " + std::to_string(column_offset + 1) : ""));
  try {
    return parse(padded, false, true);
  } catch (const InputError& e) {
    std::string what = e.what();
    const std::string prefix = "scene.K: ";
    if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
    refuse(key, shown(text) + " " + what);
  } catch (const std::exception& e) {
    refuse(key, shown(text) + " could not be analysed: " + e.what());
  }
}

// Every name the formula reads must be the scene's: q/p as the scene writes them, z, t,
// lambda, pi, a parameter.
FormulaReads check_names(const std::string& key, const std::string& text, const Parsed& parsed,
                         const SceneInfo& scene) {
  std::set<std::string> allowed;
  for (const auto& n : names_of_state(scene)) allowed.insert(n);
  for (const auto& n : parameter_names(scene)) allowed.insert(n);
  allowed.insert("pi");
  FormulaReads reads;
  std::vector<const Node*> pending{parsed.tree.get()};
  while (!pending.empty()) {
    const Node* n = pending.back();
    pending.pop_back();
    if (n == nullptr) continue;
    if (n->kind == Node::name) {
      if (!allowed.count(n->text)) {
        std::vector<std::string> state = names_of_state(scene), params = parameter_names(scene);
        refuse(key, shown(text) + " reads '" + n->text + "', which is not a symbol of scene '" +
                        scene.name + "' (its state and time: " + join(state, ", ") +
                        (params.empty() ? "; no parameters" : "; its parameters: " + join(params, ", ")) +
                        ")");
      }
      if (n->text == "z") reads.z = true;
      if (n->text == "lambda") reads.lambda = true;
      if (n->text == "t") reads.t = true;
    }
    pending.push_back(n->a.get());
    pending.push_back(n->b.get());
  }
  return reads;
}

std::string formula_code(const std::string& key, const std::string& text, const SceneInfo& scene,
                         std::size_t column_offset, FormulaReads* reads) {
  Parsed parsed = parse_formula(key, text, column_offset);
  FormulaReads r = check_names(key, text, parsed, scene);
  if (reads != nullptr) *reads |= r;
  try {
    return expression_code(parsed, field_names(parameter_names(scene)));
  } catch (const InputError& e) {
    std::string what = e.what();
    const std::string prefix = "scene.K: ";
    if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
    refuse(key, shown(text) + ": " + what);
  }
}

// ---- conditions ------------------------------------------------------------------------------

// A condition split at its top level: comparisons of formulas joined by and/or.
class ConditionParser {
 public:
  ConditionParser(const std::string& key, const std::string& text, const SceneInfo& scene)
      : key_(key), text_(text), scene_(scene) {}

  // C++ of the whole condition (a bool), and what it reads.
  std::string run(FormulaReads& reads) {
    if (text_.find_first_not_of(" \t\r\n") == std::string::npos)
      refuse(key_, "an empty condition; write comparisons such as \"q1^2 + q2^2 > 4\"");
    std::string code = disjunction(0, text_.size(), reads);
    return code;
  }

 private:
  struct Word {
    std::size_t at;
    bool is_and;
  };

  // The positions of top-level `and` / `or` between [b, e), and checks the parentheses.
  std::vector<Word> words(std::size_t b, std::size_t e) const {
    std::vector<Word> out;
    int depth = 0;
    for (std::size_t i = b; i < e;) {
      char c = text_[i];
      if (c == '(') ++depth, ++i;
      else if (c == ')') {
        if (--depth < 0) refuse(key_, "')' at column " + std::to_string(i + 1) + " without a matching '('");
        ++i;
      } else if (is_name_start(c)) {
        std::size_t j = i;
        while (j < e && is_name_char(text_[j])) ++j;
        const std::string w = text_.substr(i, j - i);
        if (depth == 0 && (w == "and" || w == "or")) out.push_back({i, w == "and"});
        if (w == "not" || w == "xor")
          refuse(key_, "'" + w + "' at column " + std::to_string(i + 1) +
                           " is not an operator of a condition: join comparisons with and / or, "
                           "and write the opposite comparison for a negation");
        i = j;
      } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
        std::size_t j = i;  // a number, with its exponent (1e-3 is no name "e")
        while (j < e && (std::isdigit(static_cast<unsigned char>(text_[j])) || text_[j] == '.')) ++j;
        if (j < e && (text_[j] == 'e' || text_[j] == 'E')) {
          ++j;
          if (j < e && (text_[j] == '+' || text_[j] == '-')) ++j;
          while (j < e && std::isdigit(static_cast<unsigned char>(text_[j]))) ++j;
        }
        i = j;
      } else {
        ++i;
      }
    }
    if (depth != 0) refuse(key_, "a '(' is never closed");
    return out;
  }

  std::string disjunction(std::size_t b, std::size_t e, FormulaReads& reads) {
    const std::vector<Word> all = words(b, e);
    std::vector<std::pair<std::size_t, std::size_t>> ors;  // the `or` parts
    std::size_t from = b;
    for (const Word& w : all)
      if (!w.is_and) ors.push_back({from, w.at}), from = w.at + 2;
    ors.push_back({from, e});
    std::vector<std::string> parts;
    for (auto [pb, pe] : ors) {
      std::vector<std::string> ands;
      std::size_t f = pb;
      for (const Word& w : all)
        if (w.is_and && w.at >= pb && w.at < pe) ands.push_back(atom(f, w.at, reads)), f = w.at + 3;
      ands.push_back(atom(f, pe, reads));
      parts.push_back(ands.size() == 1 ? ands[0] : "(" + join(ands, " & ") + ")");
    }
    return parts.size() == 1 ? parts[0] : "(" + join(parts, " | ") + ")";
  }

  std::size_t matching(std::size_t open, std::size_t e) const {
    int depth = 0;
    for (std::size_t i = open; i < e; ++i) {
      if (text_[i] == '(') ++depth;
      if (text_[i] == ')' && --depth == 0) return i;
    }
    return std::string::npos;
  }

  // A comparison op at the top level of [b, e): its position and length, and the C++ operator.
  struct Comparison {
    std::size_t at = std::string::npos, length = 0;
    std::string op;
  };

  std::vector<Comparison> comparisons(std::size_t b, std::size_t e) const {
    std::vector<Comparison> out;
    int depth = 0;
    for (std::size_t i = b; i < e; ++i) {
      char c = text_[i];
      if (c == '(') ++depth;
      if (c == ')') --depth;
      const bool eq_next = i + 1 < e && text_[i + 1] == '=';
      if (c == '=' || c == '!')
        refuse(key_, "'" + std::string(1, c) + (eq_next ? "=" : "") + "' at column " +
                         std::to_string(i + 1) +
                         ": a condition compares with <, <=, > or >= (equality of floating-point "
                         "values is not a condition a step would meet)");
      if (c == '<' || c == '>') {
        if (depth == 0) out.push_back({i, eq_next ? 2u : 1u, std::string(1, c) + (eq_next ? "=" : "")});
        if (eq_next) ++i;
      }
    }
    return out;
  }

  std::string atom(std::size_t b, std::size_t e, FormulaReads& reads) {
    while (b < e && std::isspace(static_cast<unsigned char>(text_[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(text_[e - 1]))) --e;
    if (b >= e)
      refuse(key_, "'and' / 'or' without a comparison on one side (column " +
                       std::to_string(b + 1) + ")");
    // "(...)" that holds a comparison of its own is a group
    if (text_[b] == '(' && matching(b, e) == e - 1) {
      const std::size_t ib = b + 1, ie = e - 1;
      if (!comparisons(ib, ie).empty() || !words(ib, ie).empty())
        return disjunction(ib, ie, reads);
    }
    const std::vector<Comparison> cs = comparisons(b, e);
    const std::string part = text_.substr(b, e - b);
    if (cs.empty())
      refuse(key_, "'" + part + "' at column " + std::to_string(b + 1) +
                       " is not a comparison: write formula < formula (or <=, >, >=)");
    if (cs.size() > 1)
      refuse(key_, "'" + part + "' at column " + std::to_string(b + 1) +
                       " chains comparisons; join them with and / or (a < b and b < c)");
    const Comparison& c = cs[0];
    const std::string lhs = text_.substr(b, c.at - b);
    const std::string rhs = text_.substr(c.at + c.length, e - c.at - c.length);
    const std::string l = formula_code(key_, lhs, scene_, b, &reads);
    const std::string r = formula_code(key_, rhs, scene_, c.at + c.length, &reads);
    return "((" + l + ") " + c.op + " (" + r + "))";
  }

  const std::string& key_;
  const std::string& text_;
  const SceneInfo& scene_;
};

std::string condition_code(const std::string& key, const std::string& text, const SceneInfo& scene,
                           FormulaReads& reads) {
  return ConditionParser(key, text, scene).run(reads);
}

}  // namespace

FormulaReads check_measure_formula(const std::string& key, const std::string& text,
                                   const SceneInfo& scene) {
  FormulaReads reads;
  formula_code(key, text, scene, 0, &reads);
  return reads;
}

FormulaReads check_condition(const std::string& key, const std::string& text,
                             const SceneInfo& scene) {
  FormulaReads reads;
  condition_code(key, text, scene, reads);
  return reads;
}

FormulaReads measure_formula_reads(const Measures& m, const SceneInfo& scene) {
  FormulaReads reads;
  if (m.observe)
    for (const auto& [name, text] : m.observe->formulas)
      reads |= check_measure_formula("measures.observe." + name, text, scene);
  if (m.stop) {
    reads |= check_condition("measures.stop.when", m.stop->when, scene);
    if (!m.stop->label.empty()) reads |= check_measure_formula("measures.stop.label", m.stop->label, scene);
    for (std::size_t i = 0; i < m.stop->exits.size(); ++i)
      reads |= check_condition("measures.stop.exits[" + std::to_string(i) + "]", m.stop->exits[i], scene);
  }
  return reads;
}

std::string measures_source(const Measures& m, const SceneInfo& scene,
                            const std::string& struct_name) {
  const std::size_t n = m.observe ? m.observe->formulas.size() : 0;
  FormulaReads reads;
  std::ostringstream values;
  for (std::size_t k = 0; k < n; ++k) {
    const auto& [name, text] = m.observe->formulas[k];
    values << "    v[" << k << "] = "
           << formula_code("measures.observe." + name, text, scene, 0, &reads) << ";  // " << name
           << "\n";
  }
  std::string when = "false", exit = "0.0";
  if (m.stop) {
    when = condition_code("measures.stop.when", m.stop->when, scene, reads);
    exit = "1.0";
    if (!m.stop->label.empty()) {
      exit = "std::nearbyint(" + formula_code("measures.stop.label", m.stop->label, scene, 0, &reads) + ")";
    } else if (!m.stop->exits.empty()) {
      exit = "0.0";
      for (std::size_t i = m.stop->exits.size(); i-- > 0;)
        exit = "(" + condition_code("measures.stop.exits[" + std::to_string(i) + "]", m.stop->exits[i],
                                    scene, reads) +
               " ? " + std::to_string(i + 1) + ".0 : " + exit + ")";
    }
  }
  auto flag = [](bool b) { return b ? "true" : "false"; };
  std::ostringstream s;
  s << "// The run's measures as formulas ([measures] observe, stop), generated by contactsweep\n"
    << "// (src/formula/observable_codegen.cpp).\n"
    << "namespace cs {\n\nstruct " << struct_name << " {\n"
    << "  static constexpr int observables = " << n << ";\n"
    << "  static constexpr bool stop = " << flag(m.stop.has_value()) << ";\n"
    << "  static constexpr bool reads_lambda = " << flag(reads.lambda) << ";\n"
    << "  template <class X, class C>\n"
    << "  static void observe([[maybe_unused]] const X& x, [[maybe_unused]] const C& c, "
       "[[maybe_unused]] double* v) {\n"
    << values.str() << "  }\n"
    << "  template <class X, class C>\n"
    << "  static bool stops([[maybe_unused]] const X& x, [[maybe_unused]] const C& c) {\n"
    << "    return " << when << ";\n  }\n"
    << "  // The exit channel of a stopped lane (a whole number; 0: none).\n"
    << "  template <class X, class C>\n"
    << "  static double exit([[maybe_unused]] const X& x, [[maybe_unused]] const C& c) {\n"
    << "    return " << exit << ";\n  }\n"
    << "};\n\n}  // namespace cs\n";
  return s.str();
}

}  // namespace cs
