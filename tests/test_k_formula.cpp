// scene.K, a contact Hamiltonian written in the spec (src/formula/k_formula.hpp): what it means
// (grammar, exact numbers), what the kernel learns from it (traits), what is refused and how,
// and the scene header generated from it (the last three: test_k_formula_codegen.cpp). Compiling
// the generated headers needs the run-time compiler; here the text is checked, and evaluate_k
// (GiNaC and CLN, correctly rounded) is the reference.
#include <gtest/gtest.h>

#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "formula/k_formula.hpp"

namespace cs {
namespace {

// ---- traits ------------------------------------------------------------------------------------

enum Split { none, linear, quadratic };

struct TraitCase {
  const char* what;
  const char* K;
  int dof;
  bool indexed, time_dependent, z_feeds_back, kz_constant, kz_state_free, p_in_forces;
  Split split;
  std::vector<std::string> parameters;
};

const TraitCase kTraitCases[] = {
    // what, K, dof, indexed, time_dependent, z_feeds_back, kz_constant, kz_state_free,
    // p_in_forces, z part, parameters
    {"A damped oscillator", "(p^2 + omega^2*q^2)/2 - gamma*z", 1, false, false, false, true, true,
     false, linear, {"gamma", "omega"}},
    {"B z^2 damping", "(p^2 + omega^2*q^2)/2 - gamma*z^2", 1, false, false, true, false, false,
     false, quadratic, {"gamma", "omega"}},
    {"C double well", "p^2/2 + (q^2 - a^2)^2/2 - gamma*z", 1, false, false, false, true, true,
     false, linear, {"a", "gamma"}},
    {"D coupled oscillators",
     "(p1^2 + omega1_sq*q1^2)/2 + (p2^2 + omega2_sq*q2^2)/2 + g*q1^2*q2^2 - gamma*z", 2, true,
     false, false, true, true, false, linear, {"g", "gamma", "omega1_sq", "omega2_sq"}},
    {"forced Duffing", "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z", 1, false, true,
     false, true, true, false, linear, {"F", "Omega", "delta"}},
    {"Lane-Emden n = 5: damping 2/t", "p^2/2 + q^6/6 - (2/t)*z", 1, false, true, false, false,
     true, false, linear, {}},
    {"time-perturbed Kepler", "(p1^2+p2^2)/2 - 1/sqrt(q1^2+q2^2) - alpha*sin(theta*t)*z", 2,
     true, true, false, false, true, false, linear, {"alpha", "theta"}},
    {"spin-orbit",
     "p^2/2 - (eps/2)*((1 - 5*e^2/2)*cos(2*q - 2*t) - (e/2)*cos(2*q - t) + "
     "(7*e/2)*cos(2*q - 3*t)) - eta*(z + nu*q)",
     1, false, true, false, true, true, false, linear, {"e", "eps", "eta", "nu"}},
    {"magnetic pendulum, 3 magnets",
     "(p1^2+p2^2)/2 + w^2*(q1^2+q2^2)/2 - ((q1-1)^2+q2^2+d^2)^(-1/2)"
     " - ((q1+0.5)^2+(q2-0.8660254037844386)^2+d^2)^(-1/2)"
     " - ((q1+0.5)^2+(q2+0.8660254037844386)^2+d^2)^(-1/2) - gamma*z",
     2, true, false, false, true, true, false, linear, {"d", "gamma", "w"}},
    {"p in K_z", "p^2/2 + q^2/2 - gamma*p*z", 1, false, false, true, false, false, true, none,
     {"gamma"}},
    {"p in K_q", "p^2*q^2/2", 1, false, false, false, true, true, true, none, {}},
    {"kinetic not p^2/2", "p^4/4 + q^2/2 - z", 1, false, false, false, true, true, false, none, {}},
    {"mixed c*z + d*z^2", "p^2/2 + q^2/2 - gamma*z + z^2", 1, false, false, true, false, false,
     false, none, {"gamma"}},
    {"z in the force", "p^2/2 + q*z", 1, false, false, true, false, false, false, none, {}},
    {"quadratic, time-dependent", "p^2/2 + q^2/2 - exp(-t)*z^2", 1, false, true, true, false,
     false, false, quadratic, {}},
    {"no q: still one dof", "p^2/2 - z", 1, false, false, false, true, true, false, linear, {}},
    {"no z: linear with c = 0", "p^2/2 + q^4/4", 1, false, false, false, true, true, false, linear,
     {}},
    {"z cancels", "p^2/2 + (q + z)^2 - z^2 - 2*q*z", 1, false, false, false, true, true, false,
     linear, {}},
    {"K_z = -gamma*t", "p^2/2 + q^2/2 - gamma*t*z", 1, false, true, false, false, true, false,
     linear, {"gamma"}},
    {"an unused index: dof 3, p2 missing from the kinetic part", "(p1^2 + p3^2)/2 + q1*q3", 3,
     true, false, false, true, true, false, none, {}},
    {"z inside a function", "p1^2/2 + q1^2/2 + gamma*sin(z)", 1, true, false, true, false, false,
     false, none, {"gamma"}},
    // normal() is not tried on a fraction inside a denominator (k_traits.cpp): the traits come
    // from the expanded partials, which are enough here; the second K took 61 s to analyse
    // with normal() (found by the fuzzer).
    {"a fraction in a denominator", "p^2/2 + 1/(a + 1/(q - 2) + 1/(q - 3)) - gamma*z", 1, false,
     false, false, true, true, false, linear, {"a", "gamma"}},
    {"a fraction in a denominator, p in it",
     "p^2/2 - gamma*z + 1/(b + 1/(q-2) + 1/(q-3) + 1/(q-4) + c*(p+1)*(q+2)*(q+3)*(q+4)"
     " + ((b+1)^4+1)^4)",
     1, false, false, false, true, true, true, none, {"b", "c", "gamma"}},
    {"a denominator to the fourth power, p in it",
     "p^2/2 - gamma*z + 1/(a + c*(p+1)*(q+2)*(q+3)*(b+4) + (b+1)^4 + 1)^4", 1, false, false,
     false, true, true, true, none, {"a", "b", "c", "gamma"}},
    {"sorted parameters (byte order)", "b*q + a*p + B*z + Euler*q + Catalan", 1, false, false,
     false, true, true, false, none, {"B", "Catalan", "Euler", "a", "b"}},
};

TEST(KFormulaTraits, Table) {
  for (const auto& c : kTraitCases) {
    SCOPED_TRACE(std::string(c.what) + ": " + c.K);
    KFormula f = parse_k(c.K);
    EXPECT_EQ(f.text, c.K);
    EXPECT_EQ(f.traits.dof, c.dof);
    EXPECT_EQ(f.traits.indexed, c.indexed);
    EXPECT_EQ(f.traits.time_dependent, c.time_dependent);
    EXPECT_EQ(f.traits.z_feeds_back, c.z_feeds_back);
    EXPECT_EQ(f.traits.kz_constant, c.kz_constant);
    EXPECT_EQ(f.traits.kz_state_free, c.kz_state_free);
    EXPECT_EQ(f.traits.p_in_forces, c.p_in_forces);
    std::optional<ZPart> split;
    if (c.split == linear) split = ZPart::linear;
    if (c.split == quadratic) split = ZPart::quadratic;
    EXPECT_EQ(f.traits.z_part, split);
    EXPECT_EQ(f.parameters, c.parameters);
    ASSERT_EQ(static_cast<int>(f.positions.size()), c.dof);
    ASSERT_EQ(static_cast<int>(f.momenta.size()), c.dof);
    for (int i = 0; i < c.dof; ++i) {
      std::string index = c.indexed ? std::to_string(i + 1) : "";
      EXPECT_EQ(f.positions[i], "q" + index);
      EXPECT_EQ(f.momenta[i], "p" + index);
    }
  }
}

// ---- refusals ----------------------------------------------------------------------------------

struct BadCase {
  const char* K;
  std::vector<std::string> words;  // each must be in the message
};

const BadCase kBadCases[] = {
    {"", {"empty"}},
    {"   ", {"empty"}},
    {"q + ", {"syntax error at column 3", "'+'", "no right operand"}},
    {"  q + ", {"column 5"}},
    {"p^2/2 + (q", {"syntax error at column 9", "'(' is never closed"}},
    {"sin(q", {"column 4", "never closed"}},
    {"q)", {"syntax error at column 2", "')'"}},
    {"q +* p", {"syntax error at column 4", "'*'"}},
    {"2q", {"syntax error at column 2", "2*q"}},
    {"()", {"syntax error at column 1", "empty parentheses"}},
    {"q,p", {"column 2", "','"}},
    {"p^2/2 + e*q^4E8", {"power at column 12", "exponent 400000000", "up to 64"}},
    {"p^2/2 + q^-65", {"power at column 10", "exponent -65"}},
    {"p^2/2 + (q^40)^2", {"exponent 80", "combined"}},
    {"p^2/2 + q^40*q^40", {"exponent 80", "combined"}},
    {"p^2/2 + ((2^64)^64)^64*q", {"constant beyond the range of a double"}},
    {"q + 1.2.3", {"column 8", "'.3'"}},
    {"q + 1.5e", {"column 8", "exponent"}},
    {"q # a comment", {"column 3", "'#'"}},
    {"p + ω*q", {"column 5", "'ω'"}},
    {"p^2/2\n + (q", {"line 2, column 4", "never closed"}},
    {"foo(q)", {"unknown function 'foo'", "column 1", "sin cos tan exp log sqrt abs sinh cosh tanh asin acos atan"}},
    {"p + erf(q)", {"unknown function 'erf'", "column 5", "sin cos tan"}},
    {"besselj(1, q)", {"unknown function 'besselj'"}},
    {"pow(q, 2) + p", {"unknown function 'pow'"}},
    {"sin(q, p)", {"sin", "1 argument"}},
    {"sin", {"sin", "is a function"}},
    {"q(2) + p", {"q at column 1", "variable, not a function"}},
    {"q + q1", {"mixes q (column 1) with q1 (column 5)"}},
    {"p + p2", {"mixes p", "p2"}},
    {"q^2 + p1", {"mixes q", "p1"}},
    {"q0^2 + p", {"q0", "column 1", "start at 1"}},
    {"q01 + p", {"q01", "leading zeros"}},
    {"q65 + p", {"q65", "64"}},
    {"z - gamma*t", {"no position or momentum"}},
    {"2*pi", {"no position or momentum"}},
    {"I*q", {"I at column 1", "real"}},
    {"p + Pi*q", {"Pi", "pi"}},
    {"q == 1", {"syntax error at column 3", "'=='", "not an equation"}},
    {"q < 1", {"column 3", "'<'"}},
    {"sqrt(-1)*q", {"sqrt(-1) at column 1", "not real"}},
    {"p + log(-2)", {"log(-2) at column 5", "not real"}},
    {"asin(2) + q", {"asin(2)", "not real"}},
    {"(-8)^(1/3) + q", {"not real"}},
    {"q^2^3", {"column 4", "ambiguous"}},
    {"q**2", {"column 2", "'**'", "^"}},
    {"1/0 + q", {"division by zero at column 2"}},
    // a zero base under a non-positive exponent: refused before GiNaC (it leaks when it throws)
    {"p + (q-q)^0", {"the power at column 10", "0^0"}},
    {"p + (q-q)^(q-q)", {"the power at column 10", "0^0"}},
    {"p + (q-q)^-2", {"division by zero at column 10"}},
    {"log(0)*q", {"log(0) at column 1", "no finite value"}},
    {"q + 1e400", {"1e400 at column 5", "range"}},
    // constants: exact to the double, or refused (issue 22, item 7)
    {"exp(exp(exp(9)))*q + p", {"the constant exp(exp(exp(9)))", "beyond the range of a double"}},
    {"exp(exp(700))*q + p", {"exp(exp(700))", "beyond the range of a double"}},
    {"p + exp(1000)*q", {"exp(1000)", "beyond the range of a double"}},
    {"sin(exp(1e5))*q + p", {"sin(exp(100000))", "cannot be evaluated to double precision"}},
    {"asin(1 + 1e-50)*q + p", {"asin(1 + 1e-50) at column 1", "not real"}},
    {"q*1e-400", {"1e-400", "smallest"}},
    {"p + lambda*q", {"lambda", "column 5"}},
    {"p + h*q", {"h at column 5", "step"}},
    {"p + K*q", {"K at column 5", "[scene]"}},
    {"p + _a*q", {"_a", "'_'"}},
    {"p + a__b*q", {"a__b", "'__'"}},
    {"p + q_0*q", {"q_0", "initial value"}},
    {"((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((("
     "((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((("
     "(((((((((((((((((((((((((((((((((q",
     {"nested too deeply"}},
};

TEST(KFormulaErrors, RefusedWithTheReason) {
  for (const auto& c : kBadCases) {
    SCOPED_TRACE(std::string("K = \"") + c.K + "\"");
    try {
      parse_k(c.K);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      std::string message = e.what();
      EXPECT_EQ(message.rfind("scene.K: ", 0), 0u) << message;
      for (const auto& w : c.words) EXPECT_NE(message.find(w), std::string::npos) << w << " not in: " << message;
    }
  }
}

// "At most 64 degrees of freedom" (the message for q65 above) admits the 64th itself.
TEST(KFormulaErrors, TheSixtyFourthDegreeOfFreedomIsAccepted) {
  KFormula f = parse_k("p64^2/2 + q64^2/2");
  EXPECT_EQ(f.traits.dof, 64);
  ASSERT_EQ(f.positions.size(), 64u);
  EXPECT_EQ(f.positions.back(), "q64");
  EXPECT_EQ(f.momenta.back(), "p64");
}

// Reserved words of C++ and likely macros still work: the field is renamed, the name is kept.
TEST(KFormulaErrors, CppNamesAreRenamedNotRefused) {
  KFormula f = parse_k("p^2/2 + int*q + errno*q + T*q + NAN*q + Params*q + int_*q + gamma*z");
  EXPECT_EQ(f.parameters, (std::vector<std::string>{"NAN", "Params", "T", "errno", "gamma", "int", "int_"}));
  EXPECT_EQ(parameter_fields(f),
            (std::vector<std::string>{"NAN_", "Params_", "T_", "errno_", "gamma", "int_2", "int_"}));
  std::string h = scene_header(f, "Renamed");
  EXPECT_NE(h.find("T NAN_, Params_, T_, errno_, gamma, int_2, int_;"), std::string::npos) << h;
  EXPECT_NE(h.find("c.int_2 * q<0>(x)"), std::string::npos) << h;
  EXPECT_NE(h.find("c.int_ * q<0>(x)"), std::string::npos) << h;
}

// ---- meaning: the usual precedence (not GiNaC's parser's) --------------------------------------

double eval(const std::string& K, double q, double p) {
  return evaluate_k(parse_k(K), {{"q", q}, {"p", p}, {"z", 0.0}, {"t", 0.0}});
}

TEST(KFormulaGrammar, UsualPrecedence) {
  const double q = 0.7, p = 1.3;
  EXPECT_DOUBLE_EQ(eval("-q^2 + p", q, p), -(q * q) + p);
  EXPECT_DOUBLE_EQ(eval("2*-q+3 + 0*p", q, p), -2 * q + 3);  // GiNaC's parser: 2*(3 - q)
  EXPECT_DOUBLE_EQ(eval("q^-2*p", q, p), p / (q * q));       // GiNaC's parser: q^(-2p)
  EXPECT_DOUBLE_EQ(eval("q - -p*q + 1", q, p), q + p * q + 1);  // GiNaC's parser: q + p*q - 1
  EXPECT_DOUBLE_EQ(eval("q/2/p", q, p), q / (2 * p));
  EXPECT_DOUBLE_EQ(eval("--q + p", q, p), q + p);
  EXPECT_DOUBLE_EQ(eval("2^-q*p", q, p), std::pow(2.0, -q) * p);
  EXPECT_DOUBLE_EQ(eval("(q+p)^(1/2)", q, p), std::sqrt(q + p));
  EXPECT_DOUBLE_EQ(eval("q - p + q - p", q, p), 2 * q - 2 * p);
  EXPECT_DOUBLE_EQ(eval("pi*q + p", q, p), 3.141592653589793 * q + p);
  EXPECT_DOUBLE_EQ(eval("2.5e-1*q + 1E1*p", q, p), 0.25 * q + 10 * p);
}

}  // namespace
}  // namespace cs
