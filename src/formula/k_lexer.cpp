#include "formula/k_lexer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string_view>

namespace cs::k_formula {

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

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

Token Lexer::next() {
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

void Lexer::syntax(std::size_t at, const std::string& what) const {
  fail("syntax error at " + where(text_, at) + ": " + what);
}

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

}  // namespace cs::k_formula
