// A contact Hamiltonian K(q, p, z, t) written by the user in the spec (scene.K): parsed
// (k_parser.cpp) and analysed with GiNaC (k_traits.cpp), and turned into a scene header
// (scene_codegen.cpp; physics/scene_concept.hpp) that the run-time compiler builds like a
// hand-written scene.
//
// Grammar (the usual one, as in Python or a calculator):
//   sum     = product { ("+" | "-") product }
//   product = unary { ("*" | "/") unary }
//   unary   = ("+" | "-") unary | power
//   power   = primary [ "^" { "+" | "-" } primary ]        a^b^c is refused as ambiguous
//   primary = number | name | name "(" sum ")" | "(" sum ")"
// so −q^2 = −(q^2), 2*-q+3 = −2q + 3 and q^-2*p = q^(−2)·p. Numbers are decimal (1, 0.1, 2.5e-3)
// and are kept exact (0.1 is 1/10); every number in the generated code is the double nearest to
// the exact value. Names: q, p (one degree of freedom) or q1…qN, p1…pN; z; t; pi (π); the
// functions sin cos tan exp log sqrt abs sinh cosh tanh asin acos atan; any other name is a
// parameter. GiNaC's own parser is not used: it reports no column (always 0), reads '#' as a
// comment, parses 2*-q+3 as 2(3 − q) and q^-2*p as q^(−2p), and rounds decimals to 17 digits.
//
// Not thread-safe (GiNaC keeps global state): parse and generate from one thread.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "model/run_spec.hpp"             // InputError
#include "physics/scene_concept.hpp"   // ZPart

namespace cs {

// The highest index N of q1…qN, p1…pN accepted (the kernel is compiled for N).
inline constexpr int kMaxFormulaDof = 64;

// The longest K accepted, in bytes. Parsing, analysis and code generation run in bounded stack
// and near-linear time (a 64 kB K of 3000 terms in about a second); beyond this K is refused.
inline constexpr std::size_t kMaxFormulaLength = 65536;

struct KTraits {
  int dof = 0;                  // 1 for q, p; N = the highest index written for q1..qN, p1..pN
  bool indexed = false;         // written with q1.., p1..
  bool time_dependent = false;  // K depends on t
  bool z_feeds_back = false;    // z appears in K_q, K_p or K_z (the kernel must integrate z)
  bool kz_constant = false;     // K_z depends on none of q, p, z, t (parameters are fine)
  bool kz_state_free = false;   // K_z depends at most on t (true also when kz_constant)
  bool p_in_forces = false;     // K_q or K_z depends on p
  // K = Σ p_i²/2 + V(q, t) + c(t)·z (linear; c may be 0: K without z) or + c(t)·z² (quadratic),
  // V free of p and z, c free of q, p, z; nullopt otherwise (c(t)·z + d(t)·z² included).
  std::optional<ZPart> z_part;
};

struct KFormula {
  std::string text;                     // as written
  std::vector<std::string> parameters;  // every other name written, sorted (byte order)
  std::vector<std::string> positions;   // "q" or "q1".."qN"
  std::vector<std::string> momenta;     // "p" or "p1".."pN"
  KTraits traits;
};

// Parses and analyses K. Bad input throws InputError; every message starts with "scene.K: " and
// names the symbol, function or column at fault. Any other failure while handling K (GiNaC or
// CLN giving up, memory) is an InputError too, never another exception.
KFormula parse_k(const std::string& text);

// The C++ scene header for f (from parse_k), a struct named struct_name in namespace cs. K is
// generated from the formula as written (its operations in its order; constant subexpressions
// folded to the nearest double), not from GiNaC's canonical form, whose term order follows symbol
// serial numbers: the text depends on K alone, so a run and its --resume compile the same kernel.
// Throws std::invalid_argument when struct_name is not a usable C++ name.
std::string scene_header(const KFormula& f, const std::string& struct_name);

// The name of parameter f.parameters[i] as a field of the generated Params: the parameter's own
// name, or with a '_' suffix when that name is a C++ keyword, a likely macro (errno, linux, NAN,
// M_PI, ...), T or Params.
std::vector<std::string> parameter_fields(const KFormula& f);

// K, or its partial derivative by the variable named `wrt` ("q", "p2", "z", "t"), evaluated with
// GiNaC and CLN from the exact values of the doubles given, at as many digits as it takes to round
// to the nearest double (as constants of K are folded): a reference for checks of the compiled scene. `values` must hold every variable and
// parameter K depends on (an InputError names a missing one); NaN where K is not real or finite.
double evaluate_k(const KFormula& f, const std::map<std::string, double>& values,
                  const std::string& wrt = "");

}  // namespace cs
