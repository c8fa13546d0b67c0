// Internals of scene.K shared by its parser, analysis and code generator (src/formula/): the
// formula as written (a tree, each node with its GiNaC expression), exact numbers, and the error
// every refusal throws. Not part of the interface: k_formula.hpp is.
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "formula/k_formula.hpp"

namespace cs::k_formula {

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::is_a;
using GiNaC::numeric;

// Throws the InputError of a bad K: "scene.K: " + message.
[[noreturn]] void fail(const std::string& message);

numeric exact_of(double x);                // the double's exact value
double nearest_double(const numeric& r);   // r rational: correctly rounded
std::string double_literal(double x);      // a C++ literal that reads back as x, bit for bit
// The nearest double of a constant sub-expression of K (no symbols), evaluated with CLN at as
// many digits as it needs (k_constant.cpp), or why there is none.
struct ConstantValue {
  enum Kind { finite, not_real, overflow, pole, unresolved } kind = finite;
  double value = 0.0;  // when finite
};
ConstantValue constant_value(const ex& constant);
std::string constant_problem(ConstantValue::Kind kind);  // "is beyond the range of a double", ...

bool is_name_start(char c);
bool is_name_char(char c);
std::string join(const std::vector<std::string>& parts, const std::string& sep);

// The formula as written: code is generated from this tree, so it keeps the user's structure and
// order of operations whatever GiNaC's canonical form (whose term order follows symbol serial
// numbers, i.e. what the process parsed before). `value` is the subtree as a GiNaC expression.
struct Node;
using NodePtr = std::shared_ptr<const Node>;
struct Node {
  enum Kind { number, name, neg, add, sub, mul, div, pow, call } kind = number;
  // The subtree's value; inside a chain a ± b ± c (or a */ b */ c) only when constant (only the
  // whole chain's value is made: k_parser.cpp).
  ex value;
  bool constant = false;  // the value has no symbol (q − q is constant)
  NodePtr a, b;      // operands: a alone for neg and call
  std::string text;  // the name, or the function
  Node() = default;
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  ~Node();  // without recursion: a chain of 30 000 terms is as deep
};

struct Parsed {
  ex K;
  NodePtr tree;
  std::vector<GiNaC::realsymbol> q, p;  // q[i − 1] is q_i (q alone: q[0])
  GiNaC::realsymbol z{"z"}, t{"t"};
  std::map<std::string, GiNaC::realsymbol> parameters;  // sorted by name
  int dof = 0;
  bool indexed = false;
  bool state_free = false;  // a formula in the parameters alone (a natural frequency), not K
  // A measure's formula (formula/measure_formulas.hpp): may read lambda (the symbol below) and
  // need not read q or p.
  bool observable = false;
  GiNaC::realsymbol lambda{"lambda"};
};

// The tree and GiNaC expression of K; throws InputError naming the problem (and its column).
// With state_free the formula may not read q or p (and need not).
Parsed parse(const std::string& text, bool state_free = false, bool observable = false);

// The traits the kernel needs, from GiNaC's symbolic partials of parsed.K (k_traits.cpp).
KTraits analyse(const Parsed& parsed);

// The names of the generated Params' fields for `parameters` (scene_codegen.cpp).
std::vector<std::string> fields_of(const std::vector<std::string>& parameters);

// Each parameter's field in the generated Params, by parameter name (from fields_of).
using FieldNames = std::map<std::string, std::string>;
FieldNames field_names(const std::vector<std::string>& parameters);

// The C++ of the whole tree (scene_codegen.cpp), as one expression.
std::string expression_code(const Parsed& parsed, const FieldNames& fields);

// "return <K as C++>;" for the body of the generated K (scene_codegen.cpp); refuses constants
// that are not finite doubles.
std::string return_statement(const Parsed& parsed, const FieldNames& fields);

}  // namespace cs::k_formula
