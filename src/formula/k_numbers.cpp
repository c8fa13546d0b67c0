// Exact numbers of scene.K and the doubles nearest to them (k_tree.hpp): a double's exact value,
// correct rounding of a rational, and the shortest literal that reads back bit for bit.
#include <cln/rational.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include "formula/k_tree.hpp"

namespace cs::k_formula {

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

}  // namespace cs::k_formula
