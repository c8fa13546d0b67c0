// K written as a formula (formula/k_formula.hpp), the generated code's side: literals and
// constants are the double nearest their exact value, size limits, and the scene header's text.
// The parser's traits, refusals and grammar: test_k_formula.cpp.

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

// ---- precision: literals are the double nearest to what is written ----------------------------

// K at (q, p) with z = t = 0, through GiNaC and CLN (correctly rounded).
double eval(const std::string& K, double q, double p) {
  return evaluate_k(parse_k(K), {{"q", q}, {"p", p}, {"z", 0.0}, {"t", 0.0}});
}

// The return statement of K.
std::string body(const std::string& header) {
  auto from = header.find("return ", header.find("static auto K("));
  return header.substr(from, header.find(";\n", from) - from);
}

TEST(KFormulaPrecision, LiteralsAreTheNearestDouble) {
  // exact rationals, one rounding at the end: 0.1 is 0.1, 0.1 + 0.2 is 0.3 (not 0.30000000000000004)
  EXPECT_EQ(eval("0.1*q + 0*p", 1.0, 0.0), 0.1);
  EXPECT_EQ(eval("(0.1 + 0.2)*q + 0*p", 1.0, 0.0), 0.3);
  EXPECT_EQ(eval("0.30000000000000004*q + 0*p", 1.0, 0.0), 0.30000000000000004);
  // in the generated code
  std::string h = body(scene_header(
      parse_k("0.1*q + 3.141592653589793238462643383279*p + 1e-3*q + (2/3)*p + 0.30000000000000004*q "
              "+ 123456789012345678901234567890*p + 9007199254740993*q + 9007199254740993.0000001*p"),
      "Literals"));
  for (const char* literal : {"0.1 * q<0>(x)", "3.141592653589793 * p<0>(x)", "0.001 * q<0>(x)",
                              "0.6666666666666666 * p<0>(x)", "0.30000000000000004 * q<0>(x)",
                              "1.2345678901234568e+29 * p<0>(x)",
                              "9007199254740992.0 * q<0>(x)",   // 2^53 + 1: a tie, to even
                              "9007199254740994.0 * p<0>(x)"})  // just above the tie
    EXPECT_NE(h.find(literal), std::string::npos) << literal << " not in: " << h;
}

// Constant sub-expressions are folded to the double nearest to their exact value, however large
// their arguments (GiNaC's evalf at 40 digits compiled sin(1e300) as 0.0 and cos(1e100) as 1.0;
// CLN's exp wraps its exponent: exp(exp(700)) was 1.0). Expected values: an independent
// reference, tests/support/fold_reference.py (Python's decimal module at 2900 digits, no CLN).
struct FoldCase {
  std::string constant;
  double expected;
};

// The exact decimal of an integral double (glibc's printf prints every digit).
std::string exact_integer(double x) {
  char buf[400];
  std::snprintf(buf, sizeof buf, "%.0f", x);
  return buf;
}

std::string shortest(double x) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  std::string s(buf, end);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

TEST(KFormulaPrecision, ConstantsAreTheNearestDoubleOfTheirExactValue) {
  const double muller = 6381956970095103 * 0x1p797;  // the double nearest a multiple of π/2
  const FoldCase cases[] = {
      {"sin(1e22)", -0x1.b453ab76bf397p-1},  // -0.8522008497671888, the classic reduction test
      {"sin(1e300)", -0x1.f8b4479c29f0cp-1},  // 10^300 exactly: not std::sin(1e300)
      {"cos(1e100)", -0x1.db2d8d2c9c2bcp-1},
      {"cos(1e22)", 0x1.0be2cef01c8f4p-1},
      {"tan(1e300)", 0x1.770b950ff4191p+2},
      {"sin((2^62)^16*2^31)", 0x1.205248cbdb760p-1},  // 2^1023
      {"sin(exp(exp(5)))", 0x1.ea42836ed727bp-1},     // sin(2.5e64)
      {"exp(700.5)", 0x1.8625c7d4f56c2p+1010},
      {"sinh(700)", 0x1.d945df4f8ec8ep+1008},
      {"log(3)", 0x1.193ea7aad030bp+0},
      {"1 - cos(1e-10)", 0x1.79ca10c924223p-68},  // cancellation: 5e-21
      {"cos(1e-100) - 1", -0x1.87e92154ef7acp-666},  // 0 until 1100 bits (was 0.0)
      {"tanh(300) - 1", -0x1.4dd4d0d12c071p-865},
      {"exp(-740)", 0x0.0000000000055p-1022},      // subnormal: 85 · 2^-1074
      {"exp(-745.1)", 0x0.0000000000001p-1022},
      {"4.2e-322", 0x0.0000000000055p-1022},  // a subnormal literal (was 2e-323)
      // arguments that are doubles, written as their exact decimals
      {"sin(" + exact_integer(1e300) + ")", -0x1.a2c16b010e385p-1},
      {"cos(" + exact_integer(1e300) + ")", -0x1.2699022adc4c1p-1},
      {"sin(" + exact_integer(1e100) + ")", -0x1.85c5e5b929359p-2},
      {"cos(" + exact_integer(1.7976931348623157e308) + ")", -0x1.fffe62ecfab75p-1},
      {"cos(" + exact_integer(muller) + ")", -0x1.14ae72e6ba22fp-61},  // glibc: 1 ulp off
      {"sin(" + exact_integer(muller) + ")", 1.0},
      // underflow is a value; values that are exactly 0 or 1
      {"exp(-1e300)", 0.0},
      {"-exp(-1e300)", -0.0},
      {"exp(-693148)*exp(693140)", 0x1.5fc21041027adp-12},  // e^-8: the first factor is below
                                                            // 2^-10^6, and was taken for 0
      {"log(1 + exp(-1e300))", 0.0},
      {"cos(exp(-1e300))", 1.0},
      {"1/exp(1000)", 0.0},
      {"exp(1000)*exp(-1000)", 1.0},
      {"(sqrt(2) + 1)*(sqrt(2) - 1)", 1.0},
      {"sin(pi/7) - cos(5*pi/14)", 0.0},
      {"tanh(1e300)", 1.0},
      // Signs that need no reference: tanh(x) is within 2^-54 of -1 for x < -19.1, so it rounds
      // to -1.0 (GiNaC keeps this argument, a sum, inside tanh: its sign is the folder's to find);
      // e^-750 is below 2^-1075, half the least subnormal, so -e^-750 rounds to -0.0 (IEEE
      // rounding keeps the sign; it is above 2^-1100, so the folder's rounding decides it).
      {"tanh(1 - exp(1000))", -1.0},
      {"-exp(-750)", -0.0},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.constant);
    KFormula f = parse_k("(" + c.constant + ")*q + p");
    const double folded = evaluate_k(f, {{"q", 1.0}, {"p", 0.0}});
    EXPECT_EQ(std::bit_cast<std::uint64_t>(folded), std::bit_cast<std::uint64_t>(c.expected))
        << std::hexfloat << folded << " != " << c.expected;
    const std::string code = body(scene_header(f, "Folded"));
    EXPECT_NE(code.find("return " + shortest(c.expected) + " * q<0>(x) + p<0>(x)"), std::string::npos) << code;
  }
  // glibc reduces sin's argument exactly too: an independent check where it rounds correctly
  for (double x : {1e22, 1e100, 1e300, 0x1p1023, 1.7976931348623157e308})
    EXPECT_EQ(evaluate_k(parse_k("sin(" + exact_integer(x) + ")*q + p"), {{"q", 1.0}, {"p", 0.0}}), std::sin(x)) << x;
}

// GiNaC's value at random points against the formula written in double arithmetic.
TEST(KFormulaPrecision, ReferenceMatchesDirectEvaluation) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  KFormula duffing = parse_k("p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z");
  KFormula kepler = parse_k("(p1^2+p2^2)/2 - 1/sqrt(q1^2+q2^2) - alpha*sin(theta*t)*z");
  for (int k = 0; k < 20; ++k) {
    double q = u(rng), p = u(rng), z = u(rng), t = u(rng), F = 0.1, Om = 1.2566370614359172, d = 0.25;
    std::map<std::string, double> v{{"q", q}, {"p", p}, {"z", z}, {"t", t}, {"F", F}, {"Omega", Om}, {"delta", d}};
    double K = p * p / 2 - q * q / 2 + q * q * q * q / 4 - F * q * std::cos(Om * t) - d * z;
    double scale = p * p / 2 + q * q / 2 + q * q * q * q / 4 + std::fabs(F * q) + std::fabs(d * z);
    EXPECT_NEAR(evaluate_k(duffing, v), K, 4e-16 * scale);
    EXPECT_NEAR(evaluate_k(duffing, v, "q"), -q + q * q * q - F * std::cos(Om * t), 1e-15);
    EXPECT_EQ(evaluate_k(duffing, v, "p"), p);
    EXPECT_EQ(evaluate_k(duffing, v, "z"), -d);

    double q1 = u(rng), q2 = u(rng), p1 = u(rng), p2 = u(rng), a = 0.01, th = 0.5;
    std::map<std::string, double> w{{"q1", q1}, {"q2", q2}, {"p1", p1}, {"p2", p2}, {"z", z},
                                    {"t", t}, {"alpha", a}, {"theta", th}};
    double r = std::sqrt(q1 * q1 + q2 * q2);
    double Kk = (p1 * p1 + p2 * p2) / 2 - 1 / r - a * std::sin(th * t) * z;
    EXPECT_NEAR(evaluate_k(kepler, w), Kk, 1e-15 * ((p1 * p1 + p2 * p2) / 2 + 1 / r + 1));
    EXPECT_NEAR(evaluate_k(kepler, w, "q1"), q1 / (r * r * r), 1e-15 * (1 + 1 / (r * r)));
  }
}

TEST(KFormulaPrecision, MissingValueNamesIt) {
  KFormula f = parse_k("p^2/2 - gamma*z");
  try {
    evaluate_k(f, {{"p", 1.0}, {"z", 0.0}});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gamma"), std::string::npos) << e.what();
  }
}

// ---- size: bounded stack, near-linear time, a documented limit (issue 22, item 8) --------------
// Timings are not asserted here; docs/performance.md ("K in the spec") lists them.

std::string repeated(const std::string& term, int n, const std::string& sep) {
  std::string s;
  s.reserve(static_cast<std::size_t>(n) * (term.size() + sep.size()));
  for (int i = 0; i < n; ++i) s += (i ? sep : "") + term;
  return s;
}

void expect_same_traits(const KFormula& a, const KFormula& b) {
  EXPECT_EQ(a.traits.dof, b.traits.dof);
  EXPECT_EQ(a.traits.time_dependent, b.traits.time_dependent);
  EXPECT_EQ(a.traits.z_feeds_back, b.traits.z_feeds_back);
  EXPECT_EQ(a.traits.kz_constant, b.traits.kz_constant);
  EXPECT_EQ(a.traits.kz_state_free, b.traits.kz_state_free);
  EXPECT_EQ(a.traits.p_in_forces, b.traits.p_in_forces);
  EXPECT_EQ(a.traits.z_part, b.traits.z_part);
  EXPECT_EQ(a.parameters, b.parameters);
}

// 30 000 terms (60 kB; 35 000 crashed the code generator, which recursed once per term): the
// same traits and values as 30000*q, and every term in the generated code.
TEST(KFormulaSize, LongSumIsItsSmallEquivalent) {
  const int n = 30000;
  KFormula big = parse_k("p^2/2 - gamma*z + " + repeated("q", n, "+"));
  KFormula small = parse_k("p^2/2 - gamma*z + 30000*q");
  ASSERT_LE(big.text.size(), kMaxFormulaLength);
  expect_same_traits(big, small);
  for (double q : {0.5, -1.25, 3.0})
    for (const char* wrt : {"", "q", "p", "z"}) {
      std::map<std::string, double> v{{"q", q}, {"p", 0.75}, {"z", 0.5}, {"gamma", 0.1}};
      EXPECT_EQ(evaluate_k(big, v, wrt), evaluate_k(small, v, wrt)) << q << " " << wrt;
    }
  const std::string code = body(scene_header(big, "Big"));
  std::size_t terms = 0;
  for (std::size_t at = code.find("q<0>(x)"); at != std::string::npos; at = code.find("q<0>(x)", at + 1)) ++terms;
  EXPECT_EQ(terms, static_cast<std::size_t>(n));
}

TEST(KFormulaSize, BeyondTheLimitIsRefused) {
  const std::string K = repeated("q", 35000, "+");  // 70 kB
  try {
    parse_k(K);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.K: is 69999 bytes long; K takes at most 65536"), std::string::npos)
        << e.what();
  }
}

// A sum of 200 poles took 68 s in GiNaC's normal form (common denominator of degree 200).
TEST(KFormulaSize, SumOfPoles) {
  std::string K = "p^2/2 - gamma*z";
  for (int k = 1; k <= 200; ++k) K += " + 1/(q-" + std::to_string(k) + ")";
  KFormula f = parse_k(K);
  EXPECT_EQ(f.traits.dof, 1);
  EXPECT_FALSE(f.traits.z_feeds_back);
  EXPECT_TRUE(f.traits.kz_constant);
  EXPECT_FALSE(f.traits.p_in_forces);
  EXPECT_EQ(f.traits.z_part, ZPart::linear);
  long double sum = 0, slope = 0;
  for (int k = 200; k >= 1; --k) {
    sum += 1.0L / (0.5L - k);
    slope -= 1.0L / ((0.5L - k) * (0.5L - k));
  }
  std::map<std::string, double> v{{"q", 0.5}, {"p", 0.0}, {"z", 0.0}, {"gamma", 0.1}};
  EXPECT_NEAR(evaluate_k(f, v), static_cast<double>(sum), 1e-15 * std::fabs(static_cast<double>(sum)));
  EXPECT_NEAR(evaluate_k(f, v, "q"), static_cast<double>(slope), 1e-15 * std::fabs(static_cast<double>(slope)));
}

// A product of 1100 factors: GiNaC's derivative alone took 1.1 s per partial (n products of
// n − 1 factors), 35 s at 30 kB. Its traits are read off the structure, and match those of the
// same K with 20 factors, analysed symbolically.
TEST(KFormulaSize, LongProductHasTheTraitsOfAShortOne) {
  auto product = [](int n) {
    std::string s = "c";
    for (int k = 1; k <= n; ++k) s += "*(q+" + std::to_string(k) + ")";
    return s;
  };
  for (const std::string& rest : {std::string(" - gamma*z"), std::string("*z - gamma*z"),
                                   std::string("*p*sin(t) + z^2")}) {
    SCOPED_TRACE(rest);
    KFormula big = parse_k("p^2/2 + " + product(1100) + rest);
    KFormula small = parse_k("p^2/2 + " + product(20) + rest);
    expect_same_traits(big, small);
  }
  // K_z = -t: state-free but time-dependent, so not constant; K_z = -p: the forces read p (the
  // product's K_q reads no p, so only K_z can say so). By hand, and as the short K's analysis.
  struct KzCase {
    const char* rest;
    bool kz_constant, kz_state_free, p_in_forces;
  };
  for (const KzCase& c :
       {KzCase{" - t*z", false, true, false}, KzCase{" - p*z", false, false, true}}) {
    SCOPED_TRACE(c.rest);
    KFormula big = parse_k("p^2/2 + " + product(1100) + c.rest);
    KFormula small = parse_k("p^2/2 + " + product(20) + c.rest);
    expect_same_traits(big, small);
    EXPECT_EQ(big.traits.kz_constant, c.kz_constant);
    EXPECT_EQ(big.traits.kz_state_free, c.kz_state_free);
    EXPECT_EQ(big.traits.p_in_forces, c.p_in_forces);
  }
  KFormula f = parse_k("p^2/2 + " + product(1100) + " - gamma*z");
  EXPECT_EQ(evaluate_k(f, {{"q", -1.0}, {"p", 2.0}, {"z", 1.0}, {"c", 3.0}, {"gamma", 0.5}}), 1.5);
}

// ((q+1)^64 + 1)^64 ...: expanding it was estimated small (a difference of two lgamma of 1e37)
// and then threw std::length_error from GiNaC (exit 1 "vector::reserve").
TEST(KFormulaSize, TowerOfPowers) {
  KFormula f = parse_k("(((q+1)^64+1)^64+1)^64 + p^2/2");
  EXPECT_EQ(f.traits.z_part, ZPart::linear);
  EXPECT_FALSE(f.traits.p_in_forces);
  EXPECT_EQ(evaluate_k(f, {{"q", -1.0}, {"p", 0.0}}), 0x1p64);  // ((0 + 1)^64 + 1)^64 = 2^64
  EXPECT_EQ(evaluate_k(f, {{"q", -1.0}, {"p", 4.0}}), 0x1p64 + 8.0);  // rounds to 2^64
}

// ---- the generated header ----------------------------------------------------------------------

// Every number in generated code is a double literal: a number token (not a digit inside a name,
// nor the index of q<0>) has a '.' or an exponent.
void expect_no_int_literals(const std::string& code) {
  auto is_name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
  for (std::size_t i = 0; i < code.size(); ++i) {
    if (!is_digit(code[i])) continue;
    if (i > 0 && (is_name_char(code[i - 1]) || code[i - 1] == '<')) {
      while (i + 1 < code.size() && is_name_char(code[i + 1])) ++i;  // the rest of the name
      continue;
    }
    std::size_t j = i;
    while (j < code.size() && (is_digit(code[j]) || code[j] == '.')) ++j;
    if (j < code.size() && (code[j] == 'e' || code[j] == 'E')) {
      ++j;
      if (code[j] == '+' || code[j] == '-') ++j;
      while (j < code.size() && is_digit(code[j])) ++j;
    }
    std::string number = code.substr(i, j - i);
    EXPECT_NE(number.find_first_of(".eE"), std::string::npos) << "int literal " << number << " in " << code;
    i = j;
  }
}

TEST(KFormulaHeader, ForcedDuffing) {
  KFormula f = parse_k("p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z");
  std::string h = scene_header(f, "ForcedDuffing");
  for (const char* s : {
           "// Generated by contactsweep from scene.K = \"p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z\"\n",
           "#pragma once", "#include \"physics/dual_math.hpp\"", "#include \"physics/scene_bounds.hpp\"",
           "#include \"physics/scene_concept.hpp\"", "namespace cs {", "struct ForcedDuffing {",
           "static constexpr int dof = 1;", "static constexpr bool z_feeds_back = false;",
           "static constexpr bool kz_constant = true;", "static constexpr bool time_dependent = true;",
           "static constexpr bool p_in_forces = false;", "static constexpr ZPart z_part = ZPart::linear;",
           "T F, Omega, delta;", "static Params<T> params_from(const T* v) { return {v[0], v[1], v[2]}; }",
           "static auto K(const X& x, const Params<T>& c) {", "half_square(p<0>(x))", "q<0>(x)",
           "c.Omega * t(x)", "cos(", "c.delta * z(x)", "square(square(q<0>(x))) / 4.0",
           "return beyond_bound<dof>(q, p);"})
    EXPECT_NE(h.find(s), std::string::npos) << s << " not in:\n" << h;
  expect_no_int_literals(body(h));
  EXPECT_EQ(h.find("1/2"), std::string::npos);
  EXPECT_EQ(h.find("std::"), std::string::npos);  // unqualified: dual_math.hpp's overloads
}

TEST(KFormulaHeader, NoParametersStillHaveOneField) {
  std::string h = scene_header(parse_k("p^2/2 + q^6/6 - (2/t)*z"), "LaneEmden");
  EXPECT_NE(h.find("T none_;"), std::string::npos) << h;
  EXPECT_NE(h.find("static Params<T> params_from(const T*) { return {T{}}; }"), std::string::npos) << h;
  EXPECT_NE(h.find("static auto K(const X& x, const Params<T>&) {"), std::string::npos) << h;
  EXPECT_NE(h.find("2.0 / t(x) * z(x)"), std::string::npos) << h;
  EXPECT_NE(h.find("static constexpr bool kz_constant = false;"), std::string::npos) << h;
  expect_no_int_literals(body(h));
}

TEST(KFormulaHeader, PowersAndFunctions) {
  std::string h = body(scene_header(
      parse_k("(p1^2+p2^2)/2 - 1/sqrt(q1^2+q2^2) + q1^3 + (q1+q2)^5 + q2^(-2) + q1^(3/2) + q2^0.3 "
              "+ 2^q1 + abs(p2) + exp(-t)*z^2"),
      "Powers"));
  for (const char* s : {"(square(p<0>(x)) + square(p<1>(x))) / 2.0",
                        "1.0 / sqrt(square(q<0>(x)) + square(q<1>(x)))", "square(q<0>(x)) * q<0>(x)",
                        "[](const auto& u) { return square(square(u)) * u; }(q<0>(x) + q<1>(x))",
                        "1.0 / square(q<1>(x))", "q<0>(x) * sqrt(q<0>(x))", "pow(q<1>(x), 0.3)",
                        "pow(2.0, q<0>(x))", "abs(p<1>(x))", "exp(-t(x)) * square(z(x))"})
    EXPECT_NE(h.find(s), std::string::npos) << s << " not in:\n" << h;
  expect_no_int_literals(h);
}

TEST(KFormulaHeader, CoupledAndQuadratic) {
  std::string d = scene_header(
      parse_k("(p1^2 + omega1_sq*q1^2)/2 + (p2^2 + omega2_sq*q2^2)/2 + g*q1^2*q2^2 - gamma*z"), "Coupled");
  EXPECT_NE(d.find("static constexpr int dof = 2;"), std::string::npos);
  EXPECT_NE(d.find("c.g * square(q<0>(x)) * square(q<1>(x))"), std::string::npos) << d;
  std::string b = scene_header(parse_k("(p^2 + omega^2*q^2)/2 - gamma*z^2"), "Z2");
  EXPECT_NE(b.find("static constexpr ZPart z_part = ZPart::quadratic;"), std::string::npos) << b;
  EXPECT_NE(b.find("c.gamma * square(z(x))"), std::string::npos) << b;
  std::string n = scene_header(parse_k("p^2/2 + q*z"), "NotSplit");
  EXPECT_EQ(n.find("z_part"), std::string::npos) << n;
}

// The text depends on K alone, not on what the process parsed before (GiNaC orders terms by
// symbol serial numbers): same K, same kernel, same bits on every rank and on --resume.
TEST(KFormulaHeader, SameTextWhateverCameBefore) {
  const std::string K = "p^2/2 + (q - a)^3 + (b - q)^3 + sin(a - q)*z - gamma*z + c*(q1_ + q)";
  KFormula f = parse_k(K);
  std::string first = scene_header(f, "S");
  for (const char* other : {"p^2/2 + b*a*q + c*z", "a*b*c*q1_*gamma*p", "(q1 - q2)^3 + p1"}) parse_k(other);
  EXPECT_EQ(scene_header(parse_k(K), "S"), first);
}

TEST(KFormulaHeader, TextIsEscapedInTheComment) {
  std::string h = scene_header(parse_k("p^2/2\n + q^2/2"), "Multi");
  EXPECT_EQ(h.rfind("// Generated by contactsweep from scene.K = \"p^2/2\\n + q^2/2\"\n", 0), 0u) << h;
}

TEST(KFormulaHeader, StructNameMustBeAnIdentifier) {
  KFormula f = parse_k("p^2/2");
  EXPECT_THROW(scene_header(f, "not a name"), std::invalid_argument);
  EXPECT_THROW(scene_header(f, "class"), std::invalid_argument);
  EXPECT_NO_THROW(scene_header(f, "Custom_1"));
}

}  // namespace
}  // namespace cs
