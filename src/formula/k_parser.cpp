// scene.K's parser (tokens from k_lexer.cpp): the text to a tree as written and its GiNaC
// expression, with the column of every error. The grammar, and why GiNaC's own parser is not used: k_formula.hpp.
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

#include "formula/k_lexer.hpp"
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
    // As for '/': a zero base under an exponent of real part <= 0 is never handed to GiNaC, whose
    // power(0, e) throws from inside an allocation it then never frees (LeakSanitizer, the fuzzer).
    if (base->value.is_zero() && GiNaC::is_a<GiNaC::numeric>(exponent->value)) {
      const GiNaC::numeric real_part = GiNaC::ex_to<GiNaC::numeric>(exponent->value).real();
      if (real_part.is_zero())
        fail("the power at " + at(caret) + " is 0^0, which has no value");
      if (real_part.is_negative()) fail("division by zero at " + at(caret));
    }
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
    if (tk.text == "lambda" && out_.observable) return out_.lambda;
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
    if (q_.empty() && p_.empty() && !out_.state_free && !out_.observable)
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

Parsed parse(const std::string& text, bool state_free, bool observable) {
  if (text.size() > kMaxFormulaLength)
    fail("is " + std::to_string(text.size()) + " bytes long; K takes at most " +
         std::to_string(kMaxFormulaLength) + " (write a long sum with fewer terms, or split it into parameters)");
  Parsed parsed;
  parsed.state_free = state_free;
  parsed.observable = observable;
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
