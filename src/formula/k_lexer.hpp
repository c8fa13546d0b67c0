// scene.K's lexer (k_parser.cpp's input): tokens one at a time, so that errors come in the order
// of the text, each naming its column; exact decimals. Internal to src/formula/.
#pragma once

#include <cstddef>
#include <string>

#include "formula/k_tree.hpp"

namespace cs::k_formula {

struct Token {
  enum Kind { end, number, name, op } kind = end;
  std::string text;
  std::size_t offset = 0;
};

inline bool is_digit(char c) { return c >= '0' && c <= '9'; }

// "column 7" (1-based, in characters), or "line 2, column 3" when K spans lines.
std::string where(const std::string& text, std::size_t offset);

class Lexer {
 public:
  explicit Lexer(const std::string& text) : text_(text) {}
  Token next();  // throws InputError at a character no token starts with

 private:
  [[noreturn]] void syntax(std::size_t at, const std::string& what) const;
  const std::string& text_;
  std::size_t i_ = 0;
};

// An exact decimal: digits, an optional fraction and exponent; refused beyond the double range
// (decided before any big-number arithmetic, so 1e999999999 costs nothing).
numeric exact_decimal(const std::string& literal, const std::string& text, std::size_t offset);

}  // namespace cs::k_formula
