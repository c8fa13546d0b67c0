// The C++ scene header of scene.K (k_formula.hpp, scene_header): K generated from the tree as
// written, one operation per operation in the user's order, so the text depends on K alone.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "formula/k_tree.hpp"

namespace cs::k_formula {
namespace {

constexpr std::string_view kCppKeywords[] = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break",
    "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept",
    "const", "consteval", "constexpr", "constinit", "const_cast", "continue", "co_await",
    "co_return", "co_yield", "decltype", "default", "delete", "do", "double", "dynamic_cast",
    "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto",
    "if", "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq",
    "nullptr", "operator", "or", "or_eq", "private", "protected", "public", "register",
    "reinterpret_cast", "requires", "return", "short", "signed", "sizeof", "static",
    "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local",
    "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using",
    "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq",
    // GNU keywords, the preprocessor's own name, and the generated code's own names
    "typeof", "defined", "T", "Params", "final"};

// Could `name` be a macro of the C and C++ headers (glibc's NAN, M_PI, EOF, errno, and GCC's
// predefined linux, unix in GNU mode)? Then the field is renamed rather than risk `c.1`.
bool maybe_macro(const std::string& name) {
  static const std::set<std::string, std::less<>> lower = {
      "errno", "linux", "unix", "stdin", "stdout", "stderr", "math_errhandling", "i386"};
  if (lower.count(name)) return true;
  if (name.size() >= 2 && (name.rfind("M_", 0) == 0 || name.rfind("L_", 0) == 0 || name.rfind("P_", 0) == 0))
    return true;
  bool has_lower = std::any_of(name.begin(), name.end(), [](char c) { return std::islower(static_cast<unsigned char>(c)); });
  return name.size() >= 2 && !has_lower;
}


}  // namespace

std::vector<std::string> fields_of(const std::vector<std::string>& parameters) {
  std::set<std::string> used(parameters.begin(), parameters.end());
  std::vector<std::string> fields;
  for (const auto& name : parameters) {
    bool keyword = std::find(std::begin(kCppKeywords), std::end(kCppKeywords), name) != std::end(kCppKeywords);
    if (!keyword && !maybe_macro(name)) {
      fields.push_back(name);
      continue;
    }
    std::string field = name + "_";
    for (int k = 2; used.count(field); ++k) field = name + "_" + std::to_string(k);
    used.insert(field);
    fields.push_back(field);
  }
  return fields;
}


namespace {

enum Prec { kSum = 1, kProduct = 2, kUnary = 3, kAtom = 4 };

struct Code {
  std::string s;
  int prec = kAtom;
  bool leaf = false;  // a name or a literal: cheap and safe to repeat
};

std::string wrap(const Code& c, int min_prec) { return c.prec < min_prec ? "(" + c.s + ")" : c.s; }

// The exact value when e is a rational number, else nullopt.
std::optional<numeric> rational_of(const ex& e) {
  if (is_a<numeric>(e) && ex_to<numeric>(e).is_rational()) return ex_to<numeric>(e);
  return std::nullopt;
}

std::string to_string(const ex& e) {
  std::ostringstream os;
  os << e;
  return os.str();
}

// The nearest double of a constant (k_constant.cpp); refused when it is not a finite real double.
double folded(const ex& e) {
  const ConstantValue v = constant_value(e);
  if (v.kind != ConstantValue::finite) fail("the constant " + to_string(e) + " " + constant_problem(v.kind));
  return v.value;
}

// C++ for the tree as written: one operation per operation of K, in its order (left to right),
// with these exceptions: a subtree without variables or parameters is one literal (the nearest
// double of its exact value: 2*pi, 1/3, sqrt(2)); x^2/2 is half_square(x); whole powers are
// square() and products, halves are sqrt(); numbers are double literals, never ints.
class CodeGen {
 public:
  CodeGen(const Parsed& f, const FieldNames& fields) {
    for (int i = 0; i < f.dof; ++i) {
      names_[f.q[i].get_name()] = "q<" + std::to_string(i) + ">(x)";
      names_[f.p[i].get_name()] = "p<" + std::to_string(i) + ">(x)";
    }
    names_["z"] = "z(x)";
    names_["t"] = "t(x)";
    if (f.observable) names_["lambda"] = "lambda(x)";
    for (const auto& [name, symbol] : f.parameters) names_[name] = "c." + fields.at(name);
  }

  // Left-deep chains (a + b + … as written) are walked in a loop, not a recursion as deep as the
  // chain; everything else nests no deeper than the parser allows.
  Code gen(const Node& n) const {
    if (n.constant) return literal(folded(n.value));
    switch (n.kind) {
      case Node::name: return {names_.at(n.text), kAtom, true};
      case Node::neg: return {"-" + wrap(gen(*n.a), kUnary), kUnary};
      case Node::add:
      case Node::sub: {
        std::vector<const Node*> spine;
        const Node* m = &n;
        for (; (m->kind == Node::add || m->kind == Node::sub) && !m->constant; m = m->a.get()) spine.push_back(m);
        std::string s = wrap(gen(*m), kSum);
        for (auto it = spine.rbegin(); it != spine.rend(); ++it)
          s += ((*it)->kind == Node::add ? " + " : " - ") + wrap(gen(*(*it)->b), kProduct);
        return {std::move(s), kSum};
      }
      case Node::mul:
      case Node::div: {
        if (auto x = half_square_of(n)) return {"half_square(" + gen(*x).s + ")", kAtom};
        std::vector<const Node*> spine;
        const Node* m = &n;
        for (; (m->kind == Node::mul || m->kind == Node::div) && !m->constant && !half_square_of(*m); m = m->a.get())
          spine.push_back(m);
        std::string s = wrap(gen(*m), kProduct);
        for (auto it = spine.rbegin(); it != spine.rend(); ++it)
          s += ((*it)->kind == Node::mul ? " * " : " / ") + wrap(gen(*(*it)->b), kAtom);
        return {std::move(s), kProduct};
      }
      case Node::pow: return gen_power(n);
      case Node::call: return {n.text + "(" + gen(*n.a).s + ")", kAtom};
      case Node::number: break;  // constant
    }
    fail("cannot generate code for " + to_string(n.value));
  }

  // The top-level sum with one term per line when it is long.
  std::string gen_top(const Node& root, const std::string& indent) const {
    Code whole = gen(root);
    if (whole.s.size() <= 80 || whole.prec != kSum) return whole.s;
    std::vector<std::pair<const char*, const Node*>> terms;  // the left spine of + and −
    const Node* n = &root;
    while ((n->kind == Node::add || n->kind == Node::sub) && !n->constant) {
      terms.emplace_back(n->kind == Node::add ? "+ " : "- ", n->b.get());
      n = n->a.get();
    }
    std::string out = wrap(gen(*n), kSum);
    for (auto it = terms.rbegin(); it != terms.rend(); ++it)
      out += "\n" + indent + it->first + wrap(gen(*it->second), kProduct);
    return out;
  }

 private:
  static Code literal(double x) { return {double_literal(x), std::signbit(x) ? kUnary : kAtom, true}; }

  static bool constant_equals(const Node& n, const numeric& v) {
    if (!n.constant) return false;
    auto r = rational_of(n.value);
    return r && *r == v;
  }

  // x^2/2, x^2*(1/2) or (1/2)*x^2 → x: half_square(x) has the partial x·x' with no arithmetic
  // (physics/dual.hpp) and the same value.
  static const Node* half_square_of(const Node& n) {
    auto is_square = [](const Node& m) {
      return m.kind == Node::pow && !m.constant && constant_equals(*m.b, 2);
    };
    if (n.kind == Node::div && is_square(*n.a) && constant_equals(*n.b, 2)) return n.a->a.get();
    if (n.kind == Node::mul && is_square(*n.a) && constant_equals(*n.b, numeric(1, 2))) return n.a->a.get();
    if (n.kind == Node::mul && is_square(*n.b) && constant_equals(*n.a, numeric(1, 2))) return n.b->a.get();
    return nullptr;
  }

  // u^n for n ≥ 1 by squaring, on a name u.
  static std::string power_text(const std::string& u, long n) {
    if (n == 1) return u;
    if (n == 2) return "square(" + u + ")";
    if (n % 2 == 0) return "square(" + power_text(u, n / 2) + ")";
    return power_text(u, n - 1) + " * " + u;
  }

  // b^n (n ≥ 1), times sqrt(b) when with_sqrt; a composite base is evaluated once, as the
  // argument of an immediately called lambda.
  static Code whole_power(const Code& b, long n, bool with_sqrt) {
    if (n == 1 && !with_sqrt) return b;
    if (n == 2 && !with_sqrt) return {"square(" + b.s + ")", kAtom};
    if (b.leaf) {
      std::string s = power_text(b.s, n);
      if (with_sqrt) s += " * sqrt(" + b.s + ")";
      return {s, s.rfind("square(", 0) == 0 && s.back() == ')' && !with_sqrt && n % 2 == 0 ? kAtom : kProduct};
    }
    std::string body = power_text("u", n) + (with_sqrt ? " * sqrt(u)" : "");
    return {"[](const auto& u) { return " + body + "; }(" + b.s + ")", kAtom};
  }

  Code gen_power(const Node& n) const {
    Code b = gen(*n.a);
    std::optional<numeric> r = n.b->constant ? rational_of(n.b->value) : std::nullopt;
    if (r && !r->is_zero()) {
      numeric a = abs(*r);
      std::optional<Code> pos;
      if (a.is_integer() && a <= 64) pos = whole_power(b, a.to_long(), false);
      else if (a == numeric(1, 2)) pos = Code{"sqrt(" + b.s + ")", kAtom};
      else if ((2 * a).is_integer() && a <= 64) pos = whole_power(b, (a - numeric(1, 2)).to_long(), true);
      if (pos) return *r < 0 ? Code{"1.0 / " + wrap(*pos, kAtom), kProduct} : *pos;
    }
    return {"pow(" + b.s + ", " + gen(*n.b).s + ")", kAtom};
  }

  std::map<std::string, std::string> names_;
};

std::string escaped(const std::string& text) {
  std::string s;
  for (char c : text) {
    auto u = static_cast<unsigned char>(c);
    if (c == '\\' || c == '"') s += std::string("\\") + c;
    else if (c == '\n') s += "\\n";
    else if (c == '\t') s += "\\t";
    else if (u < 0x20 || u == 0x7f) s += "?";
    else s += c;
  }
  return s;
}

bool valid_identifier(const std::string& name) {
  if (name.empty() || !is_name_start(name[0]) || name[0] == '_') return false;
  if (!std::all_of(name.begin(), name.end(), is_name_char)) return false;
  return std::find(std::begin(kCppKeywords), std::end(kCppKeywords), name) == std::end(kCppKeywords);
}

}  // namespace

FieldNames field_names(const std::vector<std::string>& parameters) {
  const std::vector<std::string> fields = fields_of(parameters);
  FieldNames names;
  for (std::size_t i = 0; i < parameters.size(); ++i) names[parameters[i]] = fields[i];
  return names;
}

std::string expression_code(const Parsed& parsed, const FieldNames& fields) {
  return CodeGen(parsed, fields).gen(*parsed.tree).s;
}

std::string return_statement(const Parsed& parsed, const FieldNames& fields) {
  return "return " + CodeGen(parsed, fields).gen_top(*parsed.tree, "           ") + ";";
}

}  // namespace cs::k_formula

namespace cs {

using namespace k_formula;

std::vector<std::string> parameter_fields(const KFormula& f) { return fields_of(f.parameters); }

namespace {

// The C++ of a formula in K's parameters alone (a natural frequency): refused when it reads the
// state or the time, or a name K does not have.
std::string parameter_code(const std::string& text, const KFormula& f, const FieldNames& fields) {
  Parsed parsed = parse(text, true);
  if (parsed.K.has(parsed.z) || parsed.K.has(parsed.t))
    fail("'" + text + "' must depend on K's parameters alone, not on the state or t");
  for (const auto& [name, symbol] : parsed.parameters)
    if (std::find(f.parameters.begin(), f.parameters.end(), name) == f.parameters.end())
      fail("'" + text + "' reads " + name + ", which is not a parameter of K");
  return expression_code(parsed, fields);
}

}  // namespace

void order_parameters(KFormula& f, const std::vector<std::string>& order) {
  std::vector<std::string> given = order, found = f.parameters;
  std::sort(given.begin(), given.end());
  std::sort(found.begin(), found.end());
  if (given != found)
    fail("K's parameters are {" + join(found, ", ") + "}, not the {" + join(given, ", ") +
         "} declared");
  f.parameters = order;
}

std::string scene_struct_name(const std::string& scene_name) {
  std::string out;
  bool upper = true;
  for (char c : scene_name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

std::string scene_header(const KFormula& f, const std::string& struct_name,
                         const SceneHeaderExtras& extras) {
  if (!valid_identifier(struct_name))
    throw std::invalid_argument("scene_header: '" + struct_name + "' is not a usable C++ name");
  Parsed parsed = parse(f.text);
  const KTraits& tr = f.traits;
  std::vector<std::string> fields = fields_of(f.parameters);
  const FieldNames field_of = field_names(f.parameters);
  std::string body = return_statement(parsed, field_of);
  auto flag = [](bool b) { return b ? "true" : "false"; };
  std::ostringstream h;
  if (extras.source_note.empty())
    h << "// Generated by contactsweep from scene.K = \"" << escaped(f.text) << "\"\n"
      << "// Do not edit: K in the spec is the source (src/formula/scene_codegen.cpp).\n";
  else
    h << "// " << extras.source_note << "\n// K = " << escaped(f.text) << "\n";
  h << "#pragma once\n\n"
    << "#include \"physics/dual_math.hpp\"\n"
    << "#include \"physics/scene_bounds.hpp\"\n"
    << "#include \"physics/scene_concept.hpp\"\n\n"
    << "namespace cs {\n\n"
    << "struct " << struct_name << " {\n";
  if (!extras.name.empty()) h << "  static constexpr const char* name = \"" << escaped(extras.name) << "\";\n";
  h << "  static constexpr int dof = " << tr.dof << ";\n"
    << "  static constexpr bool z_feeds_back = " << flag(tr.z_feeds_back) << ";\n"
    << "  static constexpr bool kz_constant = " << flag(tr.kz_constant) << ";\n"
    << "  static constexpr bool kz_state_free = " << flag(tr.kz_state_free) << ";\n"
    << "  static constexpr bool time_dependent = " << flag(tr.time_dependent) << ";\n"
    << "  static constexpr bool p_in_forces = " << flag(tr.p_in_forces) << ";\n";
  if (tr.z_part == ZPart::linear)
    h << "  static constexpr ZPart z_part = ZPart::linear;  // K = Σp²/2 + V(q, t) + c(t)·z\n";
  else if (tr.z_part == ZPart::quadratic)
    h << "  static constexpr ZPart z_part = ZPart::quadratic;  // K = Σp²/2 + V(q, t) + c(t)·z²\n";
  h << "\n  template <class T>\n  struct Params {\n";
  if (fields.empty()) {
    h << "    T none_;  // K has no parameter; one field keeps Params a non-empty aggregate\n";
  } else {
    h << "    T " << join(fields, ", ") << ";\n";
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (fields[i] != f.parameters[i])
        h << "    // " << fields[i] << " is the parameter " << f.parameters[i] << " (renamed for C++)\n";
  }
  h << "  };\n  template <class T>\n";
  if (fields.empty()) {
    h << "  static Params<T> params_from(const T*) { return {T{}}; }\n";
  } else {
    h << "  static Params<T> params_from(const T* v) { return {";
    for (std::size_t i = 0; i < fields.size(); ++i) h << (i ? ", " : "") << "v[" << i << "]";
    h << "}; }\n";
  }
  bool uses_x = body.find("(x)") != std::string::npos;
  bool uses_c = body.find("c.") != std::string::npos;
  h << "\n  template <class X, class T>\n"
    << "  static auto K(const X&" << (uses_x ? " x" : "") << ", const Params<T>&" << (uses_c ? " c" : "")
    << ") {\n    " << body << "\n  }\n\n";
  if (!extras.natural_frequencies.empty()) {
    if (static_cast<int>(extras.natural_frequencies.size()) != tr.dof)
      fail("one natural frequency per degree of freedom expected: " + std::to_string(tr.dof) +
           ", not " + std::to_string(extras.natural_frequencies.size()));
    h << "  // The natural angular frequency of each degree of freedom (sync's default).\n"
      << "  static void natural_frequencies(const Params<double>& c, double* omega) {\n";
    for (std::size_t i = 0; i < extras.natural_frequencies.size(); ++i)
      h << "    omega[" << i << "] = " << parameter_code(extras.natural_frequencies[i], f, field_of)
        << ";\n";
    h << "  }\n\n";
  }
  h << "  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }\n"
    << "};\n\n"
    << "}  // namespace cs\n";
  return h.str();
}

}  // namespace cs
