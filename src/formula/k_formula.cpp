// scene.K: lexer, parser (a tree as written, and its GiNaC expression), analysis (traits from
// GiNaC's symbolic partials) and the C++ generator (from the tree). See k_formula.hpp for the
// grammar and why GiNaC's own parser is not used.
#include "formula/k_formula.hpp"

#include <ginac/ginac.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace cs {
namespace {

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::is_a;
using GiNaC::numeric;

[[noreturn]] void fail(const std::string& message) { throw InputError("scene.K: " + message); }

constexpr std::array<std::string_view, 13> kFunctionNames = {
    "sin", "cos", "tan", "exp", "log", "sqrt", "abs", "sinh", "cosh", "tanh", "asin", "acos", "atan"};

std::string function_list() {
  std::string s;
  for (auto f : kFunctionNames) s += (s.empty() ? "" : " ") + std::string(f);
  return s;
}

bool is_function_name(std::string_view name) {
  return std::find(kFunctionNames.begin(), kFunctionNames.end(), name) != kFunctionNames.end();
}

ex apply_function(std::string_view name, const ex& a) {
  if (name == "sin") return GiNaC::sin(a);
  if (name == "cos") return GiNaC::cos(a);
  if (name == "tan") return GiNaC::tan(a);
  if (name == "exp") return GiNaC::exp(a);
  if (name == "log") return GiNaC::log(a);
  if (name == "sqrt") return GiNaC::sqrt(a);
  if (name == "abs") return GiNaC::abs(a);
  if (name == "sinh") return GiNaC::sinh(a);
  if (name == "cosh") return GiNaC::cosh(a);
  if (name == "tanh") return GiNaC::tanh(a);
  if (name == "asin") return GiNaC::asin(a);
  if (name == "acos") return GiNaC::acos(a);
  return GiNaC::atan(a);
}

// GiNaC's precision is a global; numeric checks run at 40 digits and restore it.
class DigitsGuard {
 public:
  DigitsGuard() : saved_(GiNaC::Digits) { GiNaC::Digits = 40; }
  ~DigitsGuard() { GiNaC::Digits = saved_; }
  DigitsGuard(const DigitsGuard&) = delete;
  DigitsGuard& operator=(const DigitsGuard&) = delete;

 private:
  long saved_;
};

// ---- exact numbers and doubles -----------------------------------------------------------------

// The exact rational value of a finite double.
numeric exact_of(double x) {
  if (x == 0.0) return numeric(0);
  int e = 0;
  double frac = std::frexp(x, &e);  // x = frac · 2^e, 0.5 ≤ |frac| < 1
  auto mantissa = static_cast<long long>(std::ldexp(frac, 53));
  numeric m(static_cast<long>(mantissa));
  numeric two(2);
  return e - 53 >= 0 ? m * two.power(e - 53) : m / two.power(53 - e);
}

bool even_mantissa(double x) {
  int e = 0;
  double frac = std::frexp(x, &e);
  return (static_cast<long long>(std::ldexp(frac, 53)) & 1) == 0;
}

// The double nearest to an exact rational (ties to even); ±inf beyond the double range. CLN's
// own conversion is only the starting guess: its neighbours are compared exactly.
double nearest_double(const numeric& r) {
  if (r.is_zero()) return 0.0;
  double x = r.to_double();
  if (!std::isfinite(x)) x = r > 0 ? std::numeric_limits<double>::max() : -std::numeric_limits<double>::max();
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (int guard = 0; guard < 4; ++guard) {
    double best = x;
    numeric best_err = abs(r - exact_of(x));
    for (double y : {std::nextafter(x, -inf), std::nextafter(x, inf)}) {
      if (!std::isfinite(y)) continue;
      numeric err = abs(r - exact_of(y));
      if (err < best_err || (err == best_err && even_mantissa(y) && !even_mantissa(best))) {
        best = y;
        best_err = err;
      }
    }
    if (best == x) break;
    x = best;
  }
  // Past the largest double by at least half its spacing: overflow.
  double max = std::numeric_limits<double>::max();
  if (std::fabs(x) == max) {
    numeric half_ulp = exact_of(max) - exact_of(std::nextafter(max, 0.0));
    half_ulp = half_ulp / 2;
    if (abs(r) >= exact_of(max) + half_ulp) return r > 0 ? inf : -inf;
  }
  return x;
}

// The nearest double of a real numeric (exact rationals exactly; CLN floats by CLN).
double double_of(const numeric& n) { return n.is_rational() ? nearest_double(n) : n.to_double(); }

// The shortest decimal that reads back as x, always with a '.' or an exponent (a double literal).
std::string double_literal(double x) {
  std::array<char, 64> buf{};
  auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  std::string s(buf.data(), end);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

// ---- positions in K ------------------------------------------------------------------------------

// "column 7" (1-based, in characters), or "line 2, column 3" when K spans lines.
std::string where(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      ++line;
      column = 1;
    } else if ((c & 0xC0) != 0x80) {
      ++column;  // a UTF-8 continuation byte is part of the previous character
    }
  }
  if (text.find('\n') == std::string::npos) return "column " + std::to_string(column);
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// ---- lexer ---------------------------------------------------------------------------------------

struct Token {
  enum Kind { end, number, name, op } kind = end;
  std::string text;
  std::size_t offset = 0;
};

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Tokens one at a time, so that errors come in the order of the text.
class Lexer {
 public:
  explicit Lexer(const std::string& text) : text_(text) {}

  Token next() {
    const std::size_t n = text_.size();
    while (i_ < n && (text_[i_] == ' ' || text_[i_] == '\t' || text_[i_] == '\n' || text_[i_] == '\r')) ++i_;
    if (i_ >= n) return {Token::end, "", n};
    const std::size_t start = i_;
    const char c = text_[i_];
    if (is_name_start(c)) {
      while (i_ < n && is_name_char(text_[i_])) ++i_;
      return {Token::name, text_.substr(start, i_ - start), start};
    }
    if (is_digit(c) || (c == '.' && i_ + 1 < n && is_digit(text_[i_ + 1]))) {
      while (i_ < n && is_digit(text_[i_])) ++i_;
      if (i_ < n && text_[i_] == '.') {
        ++i_;
        while (i_ < n && is_digit(text_[i_])) ++i_;
      }
      if (i_ < n && (text_[i_] == 'e' || text_[i_] == 'E')) {
        std::size_t e = i_++;
        if (i_ < n && (text_[i_] == '+' || text_[i_] == '-')) ++i_;
        if (i_ >= n || !is_digit(text_[i_]))
          syntax(e, "the number '" + text_.substr(start, i_ - start) +
                        "' has no exponent digits (write 2.5e-3, or 2*e for a parameter e)");
        while (i_ < n && is_digit(text_[i_])) ++i_;
      }
      return {Token::number, text_.substr(start, i_ - start), start};
    }
    if (c == '*' && i_ + 1 < n && text_[i_ + 1] == '*')
      syntax(start, "'**' is not an operator; write ^ for a power (q^2)");
    if (std::string_view("+-*/^(),").find(c) != std::string_view::npos) {
      ++i_;
      return {Token::op, std::string(1, c), start};
    }
    if (c == '=' || c == '<' || c == '>' || c == '!') {
      std::size_t len = (i_ + 1 < n && text_[i_ + 1] == '=') ? 2 : 1;
      syntax(start, "'" + text_.substr(start, len) +
                        "' is a comparison or assignment; K is an expression, not an equation");
    }
    std::size_t len = 1;
    auto u = static_cast<unsigned char>(c);
    if (u >= 0x80)  // show the whole UTF-8 character
      while (start + len < n && (static_cast<unsigned char>(text_[start + len]) & 0xC0) == 0x80) ++len;
    std::string shown = (u < 0x20 || u == 0x7f) ? "\\x" + std::to_string(u) : text_.substr(start, len);
    syntax(start, "unexpected character '" + shown + "'" +
                      (u >= 0x80 ? " (names are ASCII: write omega, not ω)" : ""));
  }

 private:
  [[noreturn]] void syntax(std::size_t at, const std::string& what) const {
    fail("syntax error at " + where(text_, at) + ": " + what);
  }
  const std::string& text_;
  std::size_t i_ = 0;
};

// An exact decimal: digits, an optional fraction and exponent; refused beyond the double range
// (decided before any big-number arithmetic, so 1e999999999 costs nothing).
numeric exact_decimal(const std::string& literal, const std::string& text, std::size_t offset) {
  std::string digits;
  long long exponent = 0;
  std::size_t i = 0;
  for (; i < literal.size() && is_digit(literal[i]); ++i) digits += literal[i];
  if (i < literal.size() && literal[i] == '.')
    for (++i; i < literal.size() && is_digit(literal[i]); ++i) {
      digits += literal[i];
      --exponent;
    }
  if (i < literal.size()) {  // e or E
    ++i;
    bool negative = false;
    if (literal[i] == '+' || literal[i] == '-') negative = literal[i++] == '-';
    long long e = 0;
    for (; i < literal.size(); ++i) e = std::min<long long>(e * 10 + (literal[i] - '0'), 100000);
    exponent += negative ? -e : e;
  }
  std::size_t first = digits.find_first_not_of('0');
  if (first == std::string::npos) return numeric(0);
  digits = digits.substr(first);
  // value = digits · 10^exponent, and 10^lead ≤ value < 10^(lead + 1)
  long long lead = exponent + static_cast<long long>(digits.size()) - 1;
  auto out_of_range = [&](const char* what) {
    fail("the number " + literal + " at " + where(text, offset) + " is " + what +
         " of a double (4.9e-324 to 1.8e308)");
  };
  if (lead > 309) out_of_range("beyond the range");
  if (lead < -325) out_of_range("below the smallest positive value");
  numeric value(digits.c_str());
  numeric ten(10);
  value = exponent >= 0 ? value * ten.power(exponent) : value / ten.power(-exponent);
  double x = nearest_double(value);
  if (std::isinf(x)) out_of_range("beyond the range");
  if (x == 0.0) out_of_range("below the smallest positive value");
  return value;
}

// ---- names ---------------------------------------------------------------------------------------

// A variable of K: kind 'q' or 'p' with index (0 when written without one), 'z', 't'.
struct Variable {
  char kind = 0;
  int index = 0;
};

// q, p, z, t, qN, pN; nullopt for a parameter. Refuses q0, q01, q65.
std::optional<Variable> variable_of(const std::string& name, const std::string& text, std::size_t offset) {
  if (name == "z") return Variable{'z', 0};
  if (name == "t") return Variable{'t', 0};
  if (name[0] != 'q' && name[0] != 'p') return std::nullopt;
  if (name.size() == 1) return Variable{name[0], 0};
  std::string digits = name.substr(1);
  if (!std::all_of(digits.begin(), digits.end(), is_digit)) return std::nullopt;
  std::string at = name + " at " + where(text, offset);
  std::size_t nonzero = digits.find_first_not_of('0');
  if (nonzero == std::string::npos) fail(at + ": indices start at 1 (" + name[0] + "1, " + name[0] + "2, ...)");
  if (nonzero > 0)
    fail(at + ": an index is written without leading zeros (" + name[0] + digits.substr(nonzero) + ")");
  if (digits.size() > 3 || std::stoi(digits) > kMaxFormulaDof)
    fail(at + ": at most " + std::to_string(kMaxFormulaDof) + " degrees of freedom");
  return Variable{name[0], std::stoi(digits)};
}

// Names that would be misread as something else; refused with the reason.
void refuse_reserved_parameter(const std::string& name, const std::string& text, std::size_t offset) {
  std::string at = name + " at " + where(text, offset);
  if (name == "I")
    fail(at + " is not allowed: K must be real-valued and I reads as the imaginary unit; name the "
              "parameter otherwise");
  if (name == "Pi" || name == "PI") fail(at + ": write pi for the constant π");
  if (name == "lambda")
    fail(at + ": lambda is the contact factor λ, a state variable that K cannot depend on");
  if (name == "h") fail(at + ": h names the step-size axis of [grid]; name the parameter otherwise");
  if (name == "K" || name == "name" || name == "label")
    fail(at + ": " + name + " is a key of [scene] itself; name the parameter otherwise");
  if (name[0] == '_' || name.find("__") != std::string::npos)
    fail(at + ": a parameter name may not start with '_' or contain '__' (reserved in C++)");
  // q_0, p2_0, lambda_0, ... name initial values as grid axes
  if (name.size() > 2 && name.compare(name.size() - 2, 2, "_0") == 0) {
    std::string stem = name.substr(0, name.size() - 2);
    bool state = stem == "z" || stem == "lambda" ||
                 ((stem[0] == 'q' || stem[0] == 'p') && std::all_of(stem.begin() + 1, stem.end(), is_digit));
    if (state)
      fail(at + ": " + name + " names the initial value of " + stem +
           " as a [grid] axis; name the parameter otherwise");
  }
}

// ---- the parsed formula --------------------------------------------------------------------------

// The formula as written: code is generated from this tree, so it keeps the user's structure and
// order of operations whatever GiNaC's canonical form (whose term order follows symbol serial
// numbers, i.e. what the process parsed before). `value` is the subtree as a GiNaC expression.
struct Node;
using NodePtr = std::shared_ptr<const Node>;
struct Node {
  enum Kind { number, name, neg, add, sub, mul, div, pow, call } kind = number;
  ex value;
  NodePtr a, b;      // operands: a alone for neg and call
  std::string text;  // the name, or the function
};

NodePtr make_node(Node::Kind kind, ex value, NodePtr a = {}, NodePtr b = {}, std::string text = {}) {
  auto n = std::make_shared<Node>();
  n->kind = kind;
  n->value = std::move(value);
  n->a = std::move(a);
  n->b = std::move(b);
  n->text = std::move(text);
  return n;
}

struct Parsed {
  ex K;
  NodePtr tree;
  std::vector<GiNaC::realsymbol> q, p;  // q[i − 1] is q_i (q alone: q[0])
  GiNaC::realsymbol z{"z"}, t{"t"};
  std::map<std::string, GiNaC::realsymbol> parameters;  // sorted by name
  int dof = 0;
  bool indexed = false;
};

class Parser {
 public:
  Parser(const std::string& text, Parsed& out) : text_(text), out_(out), lexer_(text) { advance(); }

  void run() {
    if (cur_.kind == Token::end)
      fail("is empty; write the contact Hamiltonian, e.g. \"p^2/2 + q^2/2 - gamma*z\"");
    out_.tree = parse_sum();
    out_.K = out_.tree->value;
    if (cur_.kind != Token::end) expected_operator();
    finish_variables();
  }

 private:
  void advance() {
    prev_ = cur_;
    cur_ = lexer_.next();
  }
  bool at_op(char c) const { return cur_.kind == Token::op && cur_.text[0] == c; }
  std::string at(std::size_t offset) const { return where(text_, offset); }
  [[noreturn]] void syntax(std::size_t offset, const std::string& what) const {
    fail("syntax error at " + at(offset) + ": " + what);
  }

  // After a complete operand, something that is not an operator.
  [[noreturn]] void expected_operator() const {
    if (at_op(')')) syntax(cur_.offset, "')' without a matching '('");
    if (at_op(',')) syntax(cur_.offset, "',' outside a function's arguments");
    std::string hint;
    if (prev_.kind == Token::number && cur_.kind == Token::name)
      hint = " (write " + prev_.text + "*" + cur_.text + ")";
    syntax(cur_.offset, "expected an operator before '" + cur_.text + "'" + hint);
  }

  template <class F>
  ex guarded(std::size_t offset, const std::string& what, F&& f) const {
    try {
      return f();
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      std::string reason = e.what();
      if (reason.find("division by zero") != std::string::npos) fail("division by zero at " + at(offset));
      fail(what + " at " + at(offset) + " has no finite value (" + reason + ")");
    }
  }

  // A constant made by a function or a power must be real: sqrt(-1), log(-2), asin(2) are not.
  void check_real(const ex& e, std::size_t from) const {
    std::string excerpt = text_.substr(from, (cur_.kind == Token::end ? text_.size() : cur_.offset) - from);
    excerpt.erase(excerpt.find_last_not_of(" \t\r\n") + 1);
    std::string message = excerpt + " at " + at(from) + " is not real; K must be real-valued";
    if (e.has(GiNaC::I)) fail(message);
    for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (is_a<GiNaC::symbol>(*it)) return;
    DigitsGuard digits;
    ex v = e.evalf();
    if (is_a<numeric>(v) && !ex_to<numeric>(v).is_real()) fail(message);
  }

  void enter(std::size_t offset) {
    if (++depth_ > 200) syntax(offset, "nested too deeply");
  }

  NodePtr binary(const Token& op, const NodePtr& lhs, const NodePtr& rhs) {
    const ex &l = lhs->value, &r = rhs->value;
    switch (op.text[0]) {
      case '+': return make_node(Node::add, guarded(op.offset, "'+'", [&] { return l + r; }), lhs, rhs);
      case '-': return make_node(Node::sub, guarded(op.offset, "'-'", [&] { return l - r; }), lhs, rhs);
      case '*': return make_node(Node::mul, guarded(op.offset, "'*'", [&] { return l * r; }), lhs, rhs);
      default: return make_node(Node::div, guarded(op.offset, "'/'", [&] { return l / r; }), lhs, rhs);
    }
  }

  NodePtr parse_sum() {
    NodePtr lhs = parse_product();
    while (at_op('+') || at_op('-')) {
      Token op = cur_;
      advance();
      lhs = binary(op, lhs, parse_product());
    }
    return lhs;
  }

  NodePtr parse_product() {
    NodePtr lhs = parse_unary();
    while (at_op('*') || at_op('/')) {
      Token op = cur_;
      advance();
      lhs = binary(op, lhs, parse_unary());
    }
    return lhs;
  }

  NodePtr parse_unary() {
    if (at_op('+') || at_op('-')) {
      bool minus = at_op('-');
      enter(cur_.offset);
      advance();
      NodePtr e = parse_unary();
      --depth_;
      return minus ? make_node(Node::neg, -e->value, e) : e;
    }
    return parse_power();
  }

  NodePtr parse_power() {
    std::size_t from = cur_.offset;
    NodePtr base = parse_primary();
    if (!at_op('^')) return base;
    std::size_t caret = cur_.offset;
    advance();
    std::vector<bool> signs;  // q^-2: signs bind to the exponent
    while (at_op('+') || at_op('-')) {
      signs.push_back(at_op('-'));
      advance();
    }
    NodePtr exponent = parse_primary();
    for (auto it = signs.rbegin(); it != signs.rend(); ++it)
      if (*it) exponent = make_node(Node::neg, -exponent->value, exponent);
    if (at_op('^')) syntax(cur_.offset, "a^b^c is ambiguous; write (a^b)^c or a^(b^c)");
    ex e = guarded(caret, "the power", [&] { return GiNaC::pow(base->value, exponent->value); });
    check_real(e, from);
    return make_node(Node::pow, e, base, exponent);
  }

  NodePtr parse_primary() {
    const Token tk = cur_;
    if (tk.kind == Token::number) {
      advance();
      return make_node(Node::number, exact_decimal(tk.text, text_, tk.offset));
    }
    if (tk.kind == Token::name) {
      advance();
      if (at_op('(')) return parse_call(tk);
      return make_node(Node::name, symbol_of(tk), {}, {}, tk.text);
    }
    if (tk.kind == Token::op) {
      if (tk.text == "(") {
        enter(tk.offset);
        advance();
        if (at_op(')')) syntax(tk.offset, "empty parentheses '()'");
        NodePtr e = parse_sum();
        if (!at_op(')')) {
          if (cur_.kind == Token::end) syntax(tk.offset, "'(' is never closed");
          expected_operator();
        }
        advance();
        --depth_;
        return e;
      }
      syntax(tk.offset, "expected a number, a name or '(' but found '" + tk.text + "'");
    }
    // the end of K where an operand is due
    if (prev_.text == "(") syntax(prev_.offset, "'(' is never closed");
    syntax(prev_.offset, "'" + prev_.text + "' at the end has no right operand");
  }

  NodePtr parse_call(const Token& name) {
    std::size_t paren = cur_.offset;
    if (name.text == "pi" || variable_of(name.text, text_, name.offset))
      fail(name.text + " at " + at(name.offset) + " is a " + (name.text == "pi" ? "constant" : "variable") +
           ", not a function (write " + name.text + "*(...) for a product)");
    if (!is_function_name(name.text))
      fail("unknown function '" + name.text + "' at " + at(name.offset) + "; the functions are " +
           function_list());
    enter(paren);
    advance();  // (
    std::vector<NodePtr> args;
    if (!at_op(')')) {
      while (true) {
        args.push_back(parse_sum());
        if (at_op(')')) break;
        if (at_op(',')) {
          advance();
          continue;
        }
        if (cur_.kind == Token::end) syntax(paren, "'(' is never closed");
        expected_operator();
      }
    }
    advance();  // )
    --depth_;
    if (args.size() != 1)
      fail(name.text + " at " + at(name.offset) + " takes 1 argument, not " + std::to_string(args.size()));
    std::string excerpt = text_.substr(name.offset, prev_.offset + 1 - name.offset);
    ex e = guarded(name.offset, excerpt, [&] { return apply_function(name.text, args[0]->value); });
    check_real(e, name.offset);
    return make_node(Node::call, e, args[0], {}, name.text);
  }

  ex symbol_of(const Token& tk) {
    if (tk.text == "pi") return GiNaC::Pi;
    if (is_function_name(tk.text))
      fail(tk.text + " at " + at(tk.offset) + " is a function; write " + tk.text + "(...)");
    auto v = variable_of(tk.text, text_, tk.offset);
    if (!v) {
      auto it = out_.parameters.find(tk.text);
      if (it == out_.parameters.end()) {
        refuse_reserved_parameter(tk.text, text_, tk.offset);
        it = out_.parameters.emplace(tk.text, GiNaC::realsymbol(tk.text)).first;
      }
      return it->second;
    }
    if (v->kind == 'z') return out_.z;
    if (v->kind == 't') return out_.t;
    // one style, q, p or q1.., p1..: the first name written of each decides
    Token& first = v->index == 0 ? first_plain_ : first_indexed_;
    if (first.kind == Token::end) first = tk;
    if (first_plain_.kind != Token::end && first_indexed_.kind != Token::end)
      fail("mixes " + first_plain_.text + " (" + at(first_plain_.offset) + ") with " + first_indexed_.text +
           " (" + at(first_indexed_.offset) + "): write one degree of freedom as q, p or several as "
           "q1..qN, p1..pN");
    auto& symbols = v->kind == 'q' ? q_ : p_;
    auto it = symbols.find(std::max(v->index, 1));
    if (it == symbols.end())
      it = symbols.emplace(std::max(v->index, 1), GiNaC::realsymbol(tk.text)).first;
    return it->second;
  }

  // The dof is the highest index written; unwritten q_i, p_i below it are made now.
  void finish_variables() {
    if (q_.empty() && p_.empty())
      fail("has no position or momentum: K must contain q or p (or q1..qN, p1..pN)");
    out_.indexed = first_indexed_.kind != Token::end;
    int n = 1;
    for (const auto& [i, s] : q_) n = std::max(n, i);
    for (const auto& [i, s] : p_) n = std::max(n, i);
    out_.dof = n;
    for (int i = 1; i <= n; ++i) {
      std::string suffix = out_.indexed ? std::to_string(i) : "";
      out_.q.push_back(q_.count(i) ? q_.at(i) : GiNaC::realsymbol("q" + suffix));
      out_.p.push_back(p_.count(i) ? p_.at(i) : GiNaC::realsymbol("p" + suffix));
    }
  }

  const std::string& text_;
  Parsed& out_;
  Lexer lexer_;
  Token cur_, prev_;
  Token first_plain_, first_indexed_;  // kind end: none yet
  std::map<int, GiNaC::realsymbol> q_, p_;
  int depth_ = 0;
};

Parsed parse(const std::string& text) {
  Parsed parsed;
  Parser(text, parsed).run();
  if (parsed.K.has(GiNaC::I)) fail("is not real-valued");
  return parsed;
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string s;
  for (const auto& part : parts) s += (s.empty() ? "" : sep) + part;
  return s;
}

// ---- analysis ------------------------------------------------------------------------------------

// An upper bound on the number of terms of e.expand(), saturating (doubles).
double expanded_terms(const ex& e) {
  if (is_a<GiNaC::add>(e)) {
    double n = 0;
    for (std::size_t i = 0; i < e.nops(); ++i) n += expanded_terms(e.op(i));
    return n;
  }
  if (is_a<GiNaC::mul>(e)) {
    double n = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) n *= expanded_terms(e.op(i));
    return n;
  }
  if (is_a<GiNaC::power>(e) && is_a<numeric>(e.op(1)) && ex_to<numeric>(e.op(1)).is_pos_integer()) {
    double m = expanded_terms(e.op(0)), n = ex_to<numeric>(e.op(1)).to_double();
    if (n > 1000) return m > 1 ? 1e300 : 1;
    return std::exp(std::lgamma(m + n) - std::lgamma(n + 1) - std::lgamma(m));  // C(m + n − 1, n)
  }
  return 1;
}

// Expanded and normalised, so that cancellations show (z·q − q·z has no z); left as it is when
// expanding would be too big (a K like (q1 + … + q64)^8): the dependencies read off it are then
// only ever too many, which is safe (z integrated, not splittable, ...).
ex simplified(const ex& e) {
  if (expanded_terms(e) > 2e4) return e;
  ex r = e.expand();
  try {
    r = GiNaC::normal(r);
  } catch (const std::exception&) {
    // normal() may give up on some functions; expand() alone decides then
  }
  return r;
}

bool depends_on_any(const ex& e, const std::vector<GiNaC::realsymbol>& symbols) {
  return std::any_of(symbols.begin(), symbols.end(), [&](const auto& s) { return e.has(s); });
}

KTraits analyse(const Parsed& f) {
  KTraits tr;
  tr.dof = f.dof;
  tr.indexed = f.indexed;
  const ex& K = f.K;
  std::vector<ex> Kq, Kp;
  for (int i = 0; i < f.dof; ++i) {
    Kq.push_back(simplified(K.diff(f.q[i])));
    Kp.push_back(simplified(K.diff(f.p[i])));
  }
  ex Kz = simplified(K.diff(f.z));
  tr.time_dependent = simplified(K).has(f.t);
  auto has_z = [&](const ex& e) { return e.has(f.z); };
  tr.z_feeds_back = std::any_of(Kq.begin(), Kq.end(), has_z) ||
                    std::any_of(Kp.begin(), Kp.end(), has_z) || has_z(Kz);
  tr.kz_state_free = !depends_on_any(Kz, f.q) && !depends_on_any(Kz, f.p) && !Kz.has(f.z);
  tr.kz_constant = tr.kz_state_free && !Kz.has(f.t);
  auto has_p = [&](const ex& e) { return depends_on_any(e, f.p); };
  tr.p_in_forces = std::any_of(Kq.begin(), Kq.end(), has_p) || has_p(Kz);

  // z part: K − Σ p²/2 free of p, then R = c·z + V or c·z² + V with c = c(t).
  ex kinetic = 0;
  for (const auto& p : f.p) kinetic += GiNaC::pow(p, 2) / 2;
  ex R = simplified(K - kinetic);
  if (depends_on_any(R, f.p)) return tr;
  auto free_of_state = [&](const ex& e) { return !depends_on_any(e, f.q) && !e.has(f.z); };
  if (Kz.is_zero()) {
    tr.z_part = ZPart::linear;  // no z at all: c = 0
  } else if (free_of_state(Kz)) {
    if (!simplified(R - Kz * f.z).has(f.z)) tr.z_part = ZPart::linear;
  } else {
    ex Kzz = simplified(Kz.diff(f.z));
    if (!Kzz.is_zero() && free_of_state(Kzz) && simplified(Kz - Kzz * f.z).is_zero() &&
        !simplified(R - Kzz / 2 * GiNaC::pow(f.z, 2)).has(f.z))
      tr.z_part = ZPart::quadratic;
  }
  return tr;
}

// ---- C++ generation ------------------------------------------------------------------------------

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

enum Prec { kSum = 1, kProduct = 2, kUnary = 3, kAtom = 4 };

struct Code {
  std::string s;
  int prec = kAtom;
  bool leaf = false;  // a name or a literal: cheap and safe to repeat
};

std::string wrap(const Code& c, int min_prec) { return c.prec < min_prec ? "(" + c.s + ")" : c.s; }

bool is_constant(const ex& e) {
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (is_a<GiNaC::symbol>(*it)) return false;
  return true;
}

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

// The nearest double of a constant (exact for rationals, from 40 digits otherwise); refused when
// it is not a finite real double.
double constant_value(const ex& e) {
  double x;
  if (auto r = rational_of(e)) {
    x = nearest_double(*r);
  } else {
    DigitsGuard digits;
    ex v = e.evalf();
    if (!is_a<numeric>(v) || !ex_to<numeric>(v).is_real()) fail(to_string(e) + " is not a real number");
    x = double_of(ex_to<numeric>(v));
  }
  if (!std::isfinite(x)) fail("the constant " + to_string(e) + " is beyond the range of a double");
  return x;
}

// C++ for the tree as written: one operation per operation of K, in its order (left to right),
// with these exceptions: a subtree without variables or parameters is one literal (the nearest
// double of its exact value: 2*pi, 1/3, sqrt(2)); x^2/2 is half_square(x); whole powers are
// square() and products, halves are sqrt(); numbers are double literals, never ints.
class CodeGen {
 public:
  CodeGen(const Parsed& f, const std::vector<std::string>& fields) {
    for (int i = 0; i < f.dof; ++i) {
      names_[f.q[i].get_name()] = "q<" + std::to_string(i) + ">(x)";
      names_[f.p[i].get_name()] = "p<" + std::to_string(i) + ">(x)";
    }
    names_["z"] = "z(x)";
    names_["t"] = "t(x)";
    std::size_t k = 0;
    for (const auto& [name, symbol] : f.parameters) names_[name] = "c." + fields[k++];
  }

  Code gen(const Node& n) const {
    if (is_constant(n.value)) return literal(constant_value(n.value));
    switch (n.kind) {
      case Node::name: return {names_.at(n.text), kAtom, true};
      case Node::neg: return {"-" + wrap(gen(*n.a), kUnary), kUnary};
      case Node::add: return {wrap(gen(*n.a), kSum) + " + " + wrap(gen(*n.b), kProduct), kSum};
      case Node::sub: return {wrap(gen(*n.a), kSum) + " - " + wrap(gen(*n.b), kProduct), kSum};
      case Node::mul:
      case Node::div: {
        if (auto x = half_square_of(n)) return {"half_square(" + gen(*x).s + ")", kAtom};
        const char* op = n.kind == Node::mul ? " * " : " / ";
        return {wrap(gen(*n.a), kProduct) + op + wrap(gen(*n.b), kAtom), kProduct};
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
    while ((n->kind == Node::add || n->kind == Node::sub) && !is_constant(n->value)) {
      terms.emplace_back(n->kind == Node::add ? "+ " : "- ", n->b.get());
      n = n->a.get();
    }
    std::string out = wrap(gen(*n), kSum);
    for (auto it = terms.rbegin(); it != terms.rend(); ++it)
      out += "\n" + indent + it->first + wrap(gen(*it->second), kProduct);
    return out;
  }

 private:
  static Code literal(double x) { return {double_literal(x), x < 0 ? kUnary : kAtom, true}; }

  static bool constant_equals(const Node& n, const numeric& v) {
    auto r = rational_of(n.value);
    return is_constant(n.value) && r && *r == v;
  }

  // x^2/2, x^2*(1/2) or (1/2)*x^2 → x: half_square(x) has the partial x·x' with no arithmetic
  // (physics/dual.hpp) and the same value.
  static const Node* half_square_of(const Node& n) {
    auto is_square = [](const Node& m) {
      return m.kind == Node::pow && !is_constant(m.value) && constant_equals(*m.b, 2);
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
    std::optional<numeric> r = is_constant(n.b->value) ? rational_of(n.b->value) : std::nullopt;
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

std::string return_statement(const Parsed& parsed, const std::vector<std::string>& fields) {
  return "return " + CodeGen(parsed, fields).gen_top(*parsed.tree, "           ") + ";";
}

std::vector<std::string> sorted_parameters(const Parsed& parsed) {
  std::vector<std::string> names;
  for (const auto& [name, symbol] : parsed.parameters) names.push_back(name);  // std::map: sorted
  return names;
}

}  // namespace

KFormula parse_k(const std::string& text) {
  Parsed parsed = parse(text);
  KFormula f;
  f.text = text;
  f.parameters = sorted_parameters(parsed);
  for (int i = 0; i < parsed.dof; ++i) {
    f.positions.push_back(parsed.q[i].get_name());
    f.momenta.push_back(parsed.p[i].get_name());
  }
  f.traits = analyse(parsed);
  // Generate once so that every refusal (a constant beyond the double range, ...) happens here.
  return_statement(parsed, fields_of(f.parameters));
  return f;
}

std::vector<std::string> parameter_fields(const KFormula& f) { return fields_of(f.parameters); }

std::string scene_header(const KFormula& f, const std::string& struct_name) {
  if (!valid_identifier(struct_name))
    throw std::invalid_argument("scene_header: '" + struct_name + "' is not a usable C++ name");
  Parsed parsed = parse(f.text);
  const KTraits& tr = f.traits;
  std::vector<std::string> fields = fields_of(f.parameters);
  std::string body = return_statement(parsed, fields);
  auto flag = [](bool b) { return b ? "true" : "false"; };

  std::ostringstream h;
  h << "// Generated by contactsweep from scene.K = \"" << escaped(f.text) << "\"\n"
    << "// Do not edit: K in the spec is the source (src/formula/k_formula.cpp).\n"
    << "#pragma once\n\n"
    << "#include \"physics/dual_math.hpp\"\n"
    << "#include \"physics/scene_bounds.hpp\"\n"
    << "#include \"physics/scene_concept.hpp\"\n\n"
    << "namespace cs {\n\n"
    << "struct " << struct_name << " {\n"
    << "  static constexpr int dof = " << tr.dof << ";\n"
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
    << ") {\n    " << body << "\n  }\n\n"
    << "  static bool diverged(const double* q, const double* p) { return beyond_bound<dof>(q, p); }\n"
    << "};\n\n"
    << "}  // namespace cs\n";
  return h.str();
}

double evaluate_k(const KFormula& f, const std::map<std::string, double>& values, const std::string& wrt) {
  Parsed parsed = parse(f.text);
  std::vector<std::pair<ex, std::string>> symbols;
  for (int i = 0; i < parsed.dof; ++i) {
    symbols.emplace_back(parsed.q[i], parsed.q[i].get_name());
    symbols.emplace_back(parsed.p[i], parsed.p[i].get_name());
  }
  symbols.emplace_back(parsed.z, "z");
  symbols.emplace_back(parsed.t, "t");
  for (const auto& [name, symbol] : parsed.parameters) symbols.emplace_back(symbol, name);

  ex e = parsed.K;
  if (!wrt.empty()) {
    auto it = std::find_if(symbols.begin(), symbols.end(), [&](const auto& s) { return s.second == wrt; });
    if (it == symbols.end() || parsed.parameters.count(wrt))
      throw InputError("scene.K: " + wrt + " is not a variable of K");
    e = e.diff(ex_to<GiNaC::symbol>(it->first));
  }
  GiNaC::exmap substitutions;
  for (const auto& [symbol, name] : symbols) {
    if (!e.has(symbol)) continue;
    auto value = values.find(name);
    if (value == values.end()) throw InputError("scene.K: no value for " + name);
    if (!std::isfinite(value->second)) return std::numeric_limits<double>::quiet_NaN();
    substitutions[symbol] = exact_of(value->second);
  }
  try {
    DigitsGuard digits;
    ex v = e.subs(substitutions).evalf();
    if (!is_a<numeric>(v) || !ex_to<numeric>(v).is_real()) return std::numeric_limits<double>::quiet_NaN();
    return double_of(ex_to<numeric>(v));
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();  // a pole: 1/q at q = 0
  }
}

}  // namespace cs

// CLN, GiNaC's number library, allocates a few bytes at start-up that it never frees; under
// LeakSanitizer that made every program that links GiNaC fail at exit (the sanitizer build's
// test discovery first). The sanitizer runtime looks this hook up by name; other builds ignore it.
// It lives here because this file is linked into every program that links GiNaC.
extern "C" [[gnu::visibility("default"), gnu::used]] const char* __lsan_default_suppressions() {
  return "leak:libcln.so\nleak:libginac.so\n";
}
