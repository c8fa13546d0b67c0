// scene.K's lexer and parser: the text to a tree as written and its GiNaC expression, with
// the column of every error. The grammar, and why GiNaC's own parser is not used: k_formula.hpp.
#include <cln/rational.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string_view>

#include "formula/k_tree.hpp"

namespace cs::k_formula {

[[noreturn]] void fail(const std::string& message) { throw InputError("scene.K: " + message); }

Node::~Node() {
  // Children owned by this node alone are taken apart here, one at a time, rather than by their
  // own destructors in a recursion as deep as the tree.
  std::vector<NodePtr> pending;
  pending.push_back(std::move(a));
  pending.push_back(std::move(b));
  while (!pending.empty()) {
    NodePtr n = std::move(pending.back());
    pending.pop_back();
    if (n && n.use_count() == 1) {
      auto& owned = const_cast<Node&>(*n);  // made non-const by make_shared<Node>
      pending.push_back(std::move(owned.a));
      pending.push_back(std::move(owned.b));
    }
  }
}

namespace {

// Powers in the K of any physics we meet are small: q^4, r^-3/2, a Lennard-Jones r^-12, a
// polytrope's q^(n+1). Far beyond that the symbolic algebra on K does not finish: the fuzzer
// found e^4E8 in a K with a fraction, whose normal form (polynomial gcds) ran for minutes, and a
// constant like 2^4E8 is computed exactly. So numeric exponents are bounded, as written and
// after GiNaC combines them (q^40*q^40 is q^80).
constexpr int kMaxExponent = 64;

bool exponent_too_large(const ex& exponent) {
  return is_a<numeric>(exponent) && GiNaC::abs(ex_to<numeric>(exponent)) > kMaxExponent;
}

std::string text_of(const ex& e) {
  std::ostringstream os;
  os << e;
  return os.str();
}

// A constant raised to a constant is computed exactly, so ((2^64)^64)^64 would grow without
// bound with every exponent small: refused once it leaves the range of a double.
bool constant_power_overflows(const ex& base, const ex& exponent) {
  if (!is_a<numeric>(base) || !is_a<numeric>(exponent)) return false;
  const numeric& b = ex_to<numeric>(base);
  if (b.is_zero() || GiNaC::abs(b) == 1) return false;
  const double magnitude = std::fabs(b.to_double());
  const double power = std::fabs(ex_to<numeric>(exponent).to_double());
  return !(magnitude > 0.0) || !std::isfinite(magnitude) ||
         std::fabs(std::log2(magnitude)) * power > 2048.0;
}

constexpr std::array<std::string_view, 13> kFunctionNames = {
    "sin", "cos", "tan", "exp", "log", "sqrt", "abs", "sinh", "cosh", "tanh", "asin", "acos", "atan"};

std::string function_list() {
  std::string s;
  for (auto f : kFunctionNames) {
    if (!s.empty()) s += ' ';
    s += f;
  }
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


}  // namespace

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
  // Below the smallest normal double the doubles are k·2^−1074: k is r·2^1074 rounded, exactly
  // (CLN's conversion flushes these to 0, and 4.2e-322 is 85 steps away from there).
  const numeric subnormal_unit = numeric(1) / numeric(2).power(1074);
  if (abs(r) < exact_of(std::numeric_limits<double>::min())) {
    const numeric scaled = abs(r) / subnormal_unit;
    numeric k(cln::floor1(cln::the<cln::cl_RA>(scaled.to_cl_N())));
    const numeric rest = scaled - k;
    if (rest > numeric(1, 2) || (rest == numeric(1, 2) && k.is_odd())) k = k + 1;
    const double x = std::ldexp(k.to_double(), -1074);
    return r < 0 ? -x : x;
  }
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

// The shortest decimal that reads back as x, always with a '.' or an exponent (a double literal).
std::string double_literal(double x) {
  std::array<char, 64> buf{};
  auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  std::string s(buf.data(), end);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

namespace {

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

}  // namespace

// ---- lexer ---------------------------------------------------------------------------------------

struct Token {
  enum Kind { end, number, name, op } kind = end;
  std::string text;
  std::size_t offset = 0;
};

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

namespace {

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

bool has_no_symbol(const ex& e) {
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (is_a<GiNaC::symbol>(*it)) return false;
  return true;
}

std::shared_ptr<Node> make_node(Node::Kind kind, ex value, NodePtr a = {}, NodePtr b = {}, std::string text = {}) {
  auto n = std::make_shared<Node>();
  n->kind = kind;
  n->value = std::move(value);
  n->constant = has_no_symbol(n->value);
  n->a = std::move(a);
  n->b = std::move(b);
  n->text = std::move(text);
  return n;
}

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
    // The message only on failure: its column costs a scan of the text up to `from`.
    auto refuse = [&](const std::string& problem) {
      std::string excerpt = text_.substr(from, (cur_.kind == Token::end ? text_.size() : cur_.offset) - from);
      excerpt.erase(excerpt.find_last_not_of(" \t\r\n") + 1);
      fail(excerpt + " at " + at(from) + " " + problem);
    };
    if (e.has(GiNaC::I)) refuse(constant_problem(ConstantValue::not_real));
    if (!has_no_symbol(e)) return;
    // A constant beyond the double range is judged where it is folded (scene_codegen.cpp): it may
    // be part of a constant that is not (1/exp(1000) is 0.0).
    const ConstantValue v = constant_value(e);
    if (v.kind == ConstantValue::not_real || v.kind == ConstantValue::pole) refuse(constant_problem(v.kind));
  }

  void enter(std::size_t offset) {
    if (++depth_ > 200) syntax(offset, "nested too deeply");
  }

  // a ± b ± c … and a */ b */ c …: the tree as written, left-deep, and the chain's GiNaC value
  // made once from all its operands (adding one term at a time copies the sum so far: quadratic
  // in its length). A node inside the chain carries a value only when it is constant (then it
  // may be folded); q − q + p folds q − q no more, the chain as a whole still would.
  NodePtr parse_chain(bool sum) {
    NodePtr lhs = sum ? parse_product() : parse_unary();
    auto continues = [&] { return sum ? at_op('+') || at_op('-') : at_op('*') || at_op('/'); };
    if (!continues()) return lhs;
    const std::size_t first_op = cur_.offset;
    GiNaC::exvector operands{lhs->value};
    std::shared_ptr<Node> node;
    while (continues()) {
      const Token op = cur_;
      advance();
      NodePtr rhs = sum ? parse_product() : parse_unary();
      const char c = op.text[0];
      const ex& r = rhs->value;
      // Refused before GiNaC sees it: its power(0, -1) throws from inside an allocation it then
      // never frees (LeakSanitizer, the fuzzer).
      if (c == '/' && r.is_zero()) fail("division by zero at " + at(op.offset));
      operands.push_back(c == '+' || c == '*' ? r
                         : c == '-'           ? -r
                                              : guarded(op.offset, "'/'", [&] { return GiNaC::pow(r, -1); }));
      node = std::make_shared<Node>();
      node->kind = c == '+' ? Node::add : c == '-' ? Node::sub : c == '*' ? Node::mul : Node::div;
      node->constant = lhs->constant && rhs->constant;
      if (node->constant) {
        const ex& l = lhs->value;
        node->value = guarded(op.offset, std::string("'") + c + "'", [&]() -> ex {
          switch (c) {
            case '+': return l + r;
            case '-': return l - r;
            case '*': return l * r;
            default: return l / r;
          }
        });
      }
      node->a = std::move(lhs);
      node->b = std::move(rhs);
      lhs = node;
    }
    node->value = guarded(first_op, sum ? "the sum" : "the product", [&]() -> ex {
      if (sum) return GiNaC::add(operands);
      return GiNaC::mul(operands);
    });
    node->constant = has_no_symbol(node->value);
    return node;
  }

  NodePtr parse_sum() { return parse_chain(true); }
  NodePtr parse_product() { return parse_chain(false); }

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
    if (exponent_too_large(exponent->value))
      fail("the power at " + at(caret) + " has the exponent " + text_of(exponent->value) +
           "; K takes numeric exponents up to " + std::to_string(kMaxExponent) + " in magnitude");
    if (constant_power_overflows(base->value, exponent->value))
      fail("the power at " + at(caret) + " is a constant beyond the range of a double");
    if (base->value.is_zero() && GiNaC::is_a<GiNaC::numeric>(exponent->value) &&
        GiNaC::ex_to<GiNaC::numeric>(exponent->value).is_negative())
      fail("division by zero at " + at(caret));  // as for '/': never handed to GiNaC
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
    if (q_.empty() && p_.empty() && !out_.state_free)
      fail("has no position or momentum: K must contain q or p (or q1..qN, p1..pN)");
    if (out_.state_free) {
      if (!q_.empty() || !p_.empty()) fail("must not read a position or momentum");
      return;
    }
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


}  // namespace

Parsed parse(const std::string& text, bool state_free) {
  if (text.size() > kMaxFormulaLength)
    fail("is " + std::to_string(text.size()) + " bytes long; K takes at most " +
         std::to_string(kMaxFormulaLength) + " (write a long sum with fewer terms, or split it into parameters)");
  Parsed parsed;
  parsed.state_free = state_free;
  Parser(text, parsed).run();
  if (parsed.K.has(GiNaC::I)) fail("is not real-valued");
  for (GiNaC::const_preorder_iterator it = parsed.K.preorder_begin(); it != parsed.K.preorder_end(); ++it)
    if (is_a<GiNaC::power>(*it) && exponent_too_large(it->op(1)))
      fail("has a power with the exponent " + text_of(it->op(1)) +
           " once its factors are combined; K takes numeric exponents up to " +
           std::to_string(kMaxExponent) + " in magnitude");
  return parsed;
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string s;
  for (const auto& part : parts) s += (s.empty() ? "" : sep) + part;
  return s;
}

}  // namespace cs::k_formula
