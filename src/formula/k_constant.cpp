// The value of a constant sub-expression of scene.K (no variable, no parameter) as the double
// nearest to its exact value, or why it has none.
//
// GiNaC's evalf() at a fixed precision is not enough: sin(1e300) at 40 digits reduces an
// argument known to 40 digits modulo 2π (it gave 0.0), and CLN's exp() wraps its exponent
// silently for huge arguments (exp(exp(700)) gave 1.0). So constants are evaluated here, node by
// node, with CLN floats at a working precision that doubles until two successive values agree
// well enough that every number between them rounds to the same double (Ziv's strategy):
//   * sin, cos and tan are not evaluated until the precision covers the argument's size (the
//     reduction modulo 2π keeps 64 bits beyond the double's 53), so sin(1e300) waits for the
//     ~1000 bits its reduction needs;
//   * a value beyond 2^1000000 in magnitude is "beyond the range of a double" before CLN sees
//     it; one below 2^-10^12 is "flushed" (Value below): an underflow is a value, exp(-1e300) is
//     0.0 and -exp(-1e300) is -0.0, and exp(-693148)*exp(693140) is still e^-8;
//   * at 5120 digits without an answer the constant is refused (sin(exp(1e5)), or a value that
//     is exactly half-way between two doubles without being a rational GiNaC knows exactly).
// Exact rationals never get here: their nearest double is computed exactly (nearest_double).
#include <cln/exception.h>
#include <cln/float.h>
#include <cln/real.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <optional>

#include "formula/k_tree.hpp"

namespace cs::k_formula {
namespace {

constexpr double kMaxLog2 = 1e6;     // beyond 2^kMaxLog2 in magnitude: refused as overflow
constexpr double kFlushLog2 = 1e12;  // below 2^−kFlushLog2: flushed (Value); CLN reaches 2^−1e17
constexpr long kFirstDigits = 40;
constexpr long kMaxDigits = 5120;  // 40 · 2^7

struct NeedMorePrecision {};
struct Refused {
  ConstantValue::Kind kind;
};

// Restores GiNaC's precision and CLN's underflow setting (both global) on every way out.
class PrecisionScope {
 public:
  PrecisionScope() : digits_(GiNaC::Digits), underflow_(cln::cl_inhibit_floating_point_underflow) {
    cln::cl_inhibit_floating_point_underflow = true;  // a CLN underflow gives 0, not an exception
  }
  ~PrecisionScope() {
    GiNaC::Digits = digits_;
    cln::cl_inhibit_floating_point_underflow = underflow_;
  }
  PrecisionScope(const PrecisionScope&) = delete;
  PrecisionScope& operator=(const PrecisionScope&) = delete;

 private:
  long digits_;
  bool underflow_;
};

// log2 |x| to within one, for a nonzero real.
double log2_magnitude(const numeric& x) {
  if (x.is_rational())
    return static_cast<double>(x.numer().int_length()) -
           static_cast<double>(x.denom().int_length());
  const cln::cl_R r = cln::the<cln::cl_R>(x.to_cl_N());
  return static_cast<double>(cln::float_exponent(cln::the<cln::cl_F>(r)));
}

numeric exact_rational(const numeric& x) {
  if (x.is_rational()) return x;
  return numeric(cln::rational(cln::the<cln::cl_R>(x.to_cl_N())));
}

// A value, or a "flushed" one: nonzero, of the sign given and below 2^−kFlushLog2 in magnitude
// (exp(−1e300) is beyond even CLN's range). Only what cannot depend on its size is computed from
// it: it adds nothing, times a value it stays flushed, cos of it is 1, its logarithm is refused.
// Between 2^−kFlushLog2 and 2^kMaxLog2 every value is CLN's own, so a flushed one times all the
// values a K of 64 kB can multiply it by stays far below the doubles.
struct Value {
  numeric v;        // when not flushed
  int flushed = 0;  // 0, or the sign of a flushed value
};

class Evaluator {
 public:
  explicit Evaluator(long digits) : bits_(static_cast<double>(digits) * 3.32) {}

  Value value(const ex& e) const {
    if (is_a<numeric>(e)) return checked(ex_to<numeric>(e));
    if (e.is_equal(GiNaC::Pi)) return checked(ex_to<numeric>(GiNaC::Pi.evalf()));
    if (is_a<GiNaC::add>(e)) {
      numeric sum = 0;
      int flushed = 0;
      double largest = -kFlushLog2;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const Value term = value(e.op(i));
        if (term.flushed == 0) {
          if (!term.v.is_zero()) largest = std::max(largest, log2_magnitude(term.v));
          sum = checked_number(sum + term.v);
        } else if (flushed == 0 || flushed == term.flushed) {
          flushed = term.flushed;
        } else {
          throw Refused{ConstantValue::unresolved};  // flushed values of both signs
        }
      }
      if (sum.is_zero())
        zero_scale_ = std::max(zero_scale_, largest);
      else
        cancelled_ = std::max(cancelled_, largest - log2_magnitude(sum));
      if (flushed != 0 && sum.is_zero()) return {0, flushed};
      return {sum};
    }
    if (is_a<GiNaC::mul>(e)) {
      numeric product = 1;
      int flushed = 0;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const Value factor = value(e.op(i));
        if (factor.flushed == 0) {
          product = checked_number(product * factor.v);
        } else {
          flushed = (flushed == 0 ? 1 : flushed) * factor.flushed;
        }
      }
      if (flushed == 0 || product.is_zero()) return {product};
      return {0, product.is_negative() ? -flushed : flushed};
    }
    if (is_a<GiNaC::power>(e)) return power(e.op(0), e.op(1));
    if (is_a<GiNaC::function>(e) && e.nops() == 1)
      return function(ex_to<GiNaC::function>(e).get_name(), value(e.op(0)));
    throw Refused{ConstantValue::unresolved};
  }

 private:
  // Not real: refused. Too large: refused. Below 2^−kFlushLog2: flushed. Exact rationals stay
  // exact only as leaves; arithmetic runs on floats of the working precision.
  Value checked(const numeric& x) const {
    if (!x.is_real()) throw Refused{ConstantValue::not_real};
    if (!x.is_zero() && log2_magnitude(x) < -kFlushLog2) return {0, x.is_negative() ? -1 : 1};
    return {checked_number(x)};
  }
  numeric checked_number(const numeric& x) const {
    if (!x.is_real()) throw Refused{ConstantValue::not_real};
    if (x.is_zero()) return x;
    const double m = log2_magnitude(x);
    if (m > kMaxLog2) throw Refused{ConstantValue::overflow};
    if (m < -kFlushLog2) throw Refused{ConstantValue::unresolved};  // not reached: CLN's range
    return x.is_rational() ? ex_to<numeric>(x.evalf()) : x;
  }

  Value power(const ex& base, const ex& exponent) const {
    const Value b = value(base);
    if (is_a<numeric>(exponent) && ex_to<numeric>(exponent).is_integer()) {
      const numeric& k = ex_to<numeric>(exponent);
      if (k.is_zero()) return {1};
      if (b.flushed != 0) {
        if (k.is_negative()) throw Refused{ConstantValue::overflow};
        return {0, k.is_odd() ? b.flushed : 1};
      }
      if (b.v.is_zero()) {
        if (k.is_negative()) throw Refused{ConstantValue::pole};
        return {0};
      }
      const double m = log2_magnitude(b.v) * k.to_double();
      if (m > kMaxLog2 + 64) throw Refused{ConstantValue::overflow};
      return checked(b.v.power(k));
    }
    const Value x = value(exponent);
    if (b.flushed < 0 || (b.flushed == 0 && b.v.is_negative()))
      throw Refused{ConstantValue::not_real};  // GiNaC's principal value
    if (b.flushed > 0) {
      // b^x = 2^(x·log2 b), log2 b < −kFlushLog2: flushed for x ≥ 2^−20
      if (x.flushed == 0 && x.v >= numeric(1, 1 << 20)) return {0, 1};
      throw Refused{ConstantValue::unresolved};
    }
    if (x.flushed != 0) {  // b^x = e^(x·ln b), |x·ln b| < 2^−kFlushLog2 · 2^20
      if (b.v.is_zero()) {
        if (x.flushed > 0) return {0};
        throw Refused{ConstantValue::pole};
      }
      return {1};
    }
    if (b.v.is_zero()) {
      if (x.v.is_positive()) return {0};
      throw Refused{ConstantValue::pole};
    }
    return exp(checked_number(x.v * GiNaC::log(b.v)));
  }

  // e^x, within the magnitudes kept.
  Value exp(const numeric& x) const {
    static const double ln2 = std::log(2.0);
    if (x > numeric(kMaxLog2 * ln2)) throw Refused{ConstantValue::overflow};
    if (x < numeric(-kFlushLog2 * ln2)) return {0, 1};
    return checked(GiNaC::exp(x));
  }

  // sin, cos, tan of x: the reduction modulo 2π needs log2|x| + 64 bits beyond the double's.
  void need_bits_for(const numeric& x) const {
    if (!x.is_zero() && log2_magnitude(x) + 53 + 64 > bits_) throw NeedMorePrecision{};
  }

  Value function(const std::string& name, const Value& arg) const {
    if (arg.flushed != 0) {  // f(a) for a below every double by far
      if (name == "sin" || name == "tan" || name == "sinh" || name == "tanh" || name == "asin" ||
          name == "atan")
        return arg;  // f(a) = a(1 + O(a²))
      if (name == "cos" || name == "cosh" || name == "exp") return {1};
      if (name == "acos") return {ex_to<numeric>((GiNaC::Pi / 2).evalf())};
      if (name == "abs") return {0, 1};
      throw Refused{ConstantValue::unresolved};  // log
    }
    const numeric& a = arg.v;
    if (name == "sin" || name == "cos" || name == "tan") {
      need_bits_for(a);
      if (name == "sin") return checked(GiNaC::sin(a));
      if (name == "cos") return checked(GiNaC::cos(a));
      return checked(GiNaC::tan(a));
    }
    if (name == "exp") return exp(a);
    if (name == "sinh" || name == "cosh") {
      exp(GiNaC::abs(a));  // refuses what overflows
      return checked(name == "sinh" ? GiNaC::sinh(a) : GiNaC::cosh(a));
    }
    if (name == "tanh") {
      if (GiNaC::abs(a) > numeric(bits_))
        return {a.is_positive() ? 1 : -1};  // 1 − |tanh| < 2^−bits
      return checked(GiNaC::tanh(a));
    }
    if (name == "log") {
      if (a.is_zero()) throw Refused{ConstantValue::pole};
      if (a.is_negative()) throw Refused{ConstantValue::not_real};
      return checked(GiNaC::log(a));
    }
    if (name == "abs") return {GiNaC::abs(a)};
    if (name == "asin" || name == "acos") {
      if (GiNaC::abs(a) > 1) throw Refused{ConstantValue::not_real};
      return checked(name == "asin" ? GiNaC::asin(a) : GiNaC::acos(a));
    }
    if (name == "atan") return checked(GiNaC::atan(a));
    throw Refused{ConstantValue::unresolved};
  }

  double bits_;
  // What sums cancelled: the bits lost (largest term against the sum), and the size of the
  // largest term of a sum that came out exactly 0 (cos(1e-100) − 1 is 0 until 1100 bits).
  mutable double cancelled_ = 0, zero_scale_ = -kFlushLog2;

 public:
  // A lower bound on the error of a result v at this precision, in log2: a few units in its
  // last place, more where sums cancelled.
  double error_floor_log2(const numeric& v) const {
    const double own = v.is_zero() ? -kFlushLog2 : log2_magnitude(v) + cancelled_;
    return std::max(own, zero_scale_) - bits_ + 16;
  }
};

ConstantValue evaluate(const ex& e) {
  PrecisionScope scope;
  std::optional<numeric> previous;
  for (long digits = kFirstDigits; digits <= kMaxDigits; digits *= 2) {
    GiNaC::Digits = digits;
    const Evaluator evaluator(digits);
    Value value;
    try {
      value = evaluator.value(e);
    } catch (const NeedMorePrecision&) {
      continue;
    } catch (const Refused& r) {
      return {r.kind};
    } catch (const cln::floating_point_overflow_exception&) {
      return {ConstantValue::overflow};
    } catch (const cln::division_by_0_exception&) {
      return {ConstantValue::pole};
    } catch (const std::exception&) {
      return {ConstantValue::unresolved};
    }
    if (value.flushed != 0) return {ConstantValue::finite, value.flushed < 0 ? -0.0 : 0.0};
    const numeric& v = value.v;
    // Far outside the doubles, the value's size decides (and its exact rational would be huge).
    if (!v.is_zero() && !v.is_rational()) {
      const double m = log2_magnitude(v);
      if (m > 1100) return {ConstantValue::overflow};
      if (m < -1100) return {ConstantValue::finite, v.is_negative() ? -0.0 : 0.0};
    }
    if (previous) {
      // The error of v is taken as its distance to the less precise value, and at least a few
      // units in its last place, more where sums cancelled: then a cancellation is not taken
      // for its result (cos(1e-100) − 1 is 0 at 80 digits), and a value exactly half-way
      // between two doubles never passes (its rounding would depend on digits not computed).
      numeric err = GiNaC::abs(v - *previous);
      const long floor_log2 =
          std::max(-1200L, static_cast<long>(std::floor(evaluator.error_floor_log2(v))));
      const numeric ulps = numeric(2).power(floor_log2);
      if (err < ulps) err = ulps;
      const numeric low = exact_rational(v) - exact_rational(err),
                    high = exact_rational(v) + exact_rational(err);
      const double a = nearest_double(low), b = nearest_double(high);
      if (a == b) {  // also -0.0 == 0.0
        if (std::isinf(a)) return {ConstantValue::overflow};
        if (a == 0.0) return {ConstantValue::finite, high.is_negative() ? -0.0 : 0.0};
        return {ConstantValue::finite, a};
      }
    }
    previous = v;
  }
  return {ConstantValue::unresolved};
}

}  // namespace

ConstantValue constant_value(const ex& e) {
  if (is_a<numeric>(e) && ex_to<numeric>(e).is_rational()) {
    const double x = nearest_double(ex_to<numeric>(e));
    return std::isfinite(x) ? ConstantValue{ConstantValue::finite, x}
                            : ConstantValue{ConstantValue::overflow};
  }
  // The parser checks a constant where it is written, the code generator folds it: evaluated
  // once. (GiNaC is not thread-safe, and neither is this.)
  static std::map<ex, ConstantValue, GiNaC::ex_is_less> known;
  if (auto it = known.find(e); it != known.end()) return it->second;
  if (known.size() >= 4096) known.clear();
  return known[e] = evaluate(e);
}

std::string constant_problem(ConstantValue::Kind kind) {
  switch (kind) {
    case ConstantValue::not_real: return "is not real; K must be real-valued";
    case ConstantValue::overflow: return "is beyond the range of a double";
    case ConstantValue::pole: return "has no finite value (a pole)";
    case ConstantValue::unresolved:
      return "cannot be evaluated to double precision (at 5120 digits)";
    case ConstantValue::finite: break;
  }
  return "";
}

}  // namespace cs::k_formula
