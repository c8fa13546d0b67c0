// Elementary functions for the lane loop: exp, log, sin, cos, tan, sinh, cosh, tanh, asin, acos,
// atan, pow (and sqrt, abs, which are std's: IEEE-exact and vectorised by GCC).
//
// Why not std::sin and friends: a call to libm stops GCC from vectorising the loop over lanes,
// and a lane's bits must not depend on whether and how its loop was vectorised, nor on ranks,
// threads or lane position (docs/architecture.md, "same spec, same bits"). These functions use
// IEEE +, −, ×, ÷ and sqrt only (no std::fma, contraction off), exact bit manipulations through
// std::bit_cast, the exact rounding (x + 1.5·2^52) − 1.5·2^52 and selects as blends of bits;
// no table lookups, no branch on data. Every path computes the same operations in the same
// order, so scalar, SSE2, AVX2 and AVX-512 code give identical bits (tests/test_lane_math.cpp
// checks the vectorised loop against scalar calls, and a checksum of the bits across builds).
// NaN results (but sqrt's) are the one quiet NaN: no payload depends on operand order.
//
// Cost (median of 7 runs of a 64-lane loop, development machine): 1.1–3 ns a call with
// AVX-512 (tanh 4.8, pow 8.4), 1.9–6 ns with AVX2 (tanh 9.6, pow 15); glibc's scalar calls take
// 2.6–11 ns. Called one value at a time they are 2–7× slower than glibc: use them in lane loops.
//
// Accuracy: max error in ulps against long double, 10^5 points per range (test_lane_math.cpp):
//   exp   0.53 (|x| ≤ 708)                      log  0.80 (all positive doubles, subnormals)
//   sin   0.71, cos 0.70 (|x| < 3.37e9)         tan  0.82 (|x| < 3.37e9)
//   sinh  0.56, cosh 0.52, tanh 0.55 (all x)    asin 0.80, acos 0.76, atan 0.75 (all x)
//   pow   0.85 (|y·log x| ≤ 700), 0.52 (pow(x, 2.5) over 2^±60)
// Subnormal results of exp and pow are rounded twice (0.75 ulp of the subnormal measured).
//
// Methods: Cody–Waite reduction and minimax polynomials (a Remez exchange in 100-digit mpmath,
// rounded to double) in fdlibm's formulations, with double-double steps (Dekker's exact
// products, Veltkamp's split) where one rounding would cost a good part of an ulp: 1 + r + r²/2
// in exp, the reduced trigonometric argument, r² in cos, the quotient in tan and tanh, e^±x in
// the hyperbolic functions, log x and y·log x in pow.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cs::lane_math {

// c ? a : b as a blend of bits, for callers' lane loops too. A ternary would not do: GCC moves
// the computation of a value used on one side only into that side, and then cannot vectorise
// the loop without masked instructions (AVX-512 has them, AVX2 does not), because
// -ftrapping-math forbids executing floating-point operations speculatively. Here both values
// are always used. Keep the condition one comparison: && and || become control flow too.
[[gnu::always_inline]] inline double select(bool c, double a, double b) {
  const std::uint64_t m = std::uint64_t{0} - std::uint64_t{c};
  return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & m) |
                               (std::bit_cast<std::uint64_t>(b) & ~m));
}

// a·b + c rounded once (std::fma: exact by definition, so the same bits scalar or vectorised,
// on any CPU; one vfmadd where the build has FMA). The integrators write their updates
// x + h·f and p − h·K_q with it: fewer operations on the kernel's busiest pipes, one rounding
// less (README, Benchmarks: "FMA, a decision"). Contraction stays off, so nothing else is
// ever fused.
[[gnu::always_inline]] inline double mul_add(double a, double b, double c) {
  return std::fma(a, b, c);
}

namespace detail {

using u64 = std::uint64_t;
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

[[gnu::always_inline]] inline u64 bits(double x) { return std::bit_cast<u64>(x); }
[[gnu::always_inline]] inline double from_bits(u64 b) { return std::bit_cast<double>(b); }

// NaN results as the one quiet NaN: where two NaNs with different payloads meet (an input NaN and
// one made inside), the payload kept would depend on the operand order the compiler chose.
[[gnu::always_inline]] inline double canonical(double r) { return select(r == r, r, nan); }

// |x| with the sign of s, on the bits (a select would lose the sign of zero).
[[gnu::always_inline]] inline double copysign(double x, double s) {
  constexpr u64 sign = u64{1} << 63;
  return from_bits((bits(x) & ~sign) | (bits(s) & sign));
}

// The nearest integer to x (ties to even) for |x| < 2^51, exactly.
constexpr double round_shift = 0x1.8p52;
[[gnu::always_inline]] inline double round_int(double x) { return (x + round_shift) - round_shift; }

// 2^k for an integer-valued k in [−1022, 1023]: the exponent field written directly.
[[gnu::always_inline]] inline double pow2(double k) {
  return from_bits(bits(k + (0x1p52 + 1023.0)) << 52);
}

// y·2^k for an integer-valued |k| ≤ 1100, in two exact halves so that neither factor over- or
// underflows; only a subnormal result is rounded (once).
[[gnu::always_inline]] inline double scale(double y, double k) {
  const double k1 = round_int(0.5 * k);
  return (y * pow2(k1)) * pow2(k - k1);
}

// p(x) = c0 + x·(c1 + x·(c2 + …)), in this order on every path.
[[gnu::always_inline]] inline double horner(double, double c0) { return c0; }
template <class... C>
[[gnu::always_inline]] inline double horner(double x, double c0, C... c) {
  return c0 + x * horner(x, c...);
}

// Double-double: an unevaluated sum hi + lo, |lo| much smaller than |hi|.
struct DD {
  double hi, lo;
};

// a + b = s + e exactly (Knuth), for any magnitudes.
[[gnu::always_inline]] inline DD two_sum(double a, double b) {
  const double s = a + b;
  const double bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

// a + b = s + e exactly when |a| ≥ |b| (Dekker).
[[gnu::always_inline]] inline DD fast_two_sum(double a, double b) {
  const double s = a + b;
  return {s, b - (s - a)};
}

// a = hi + lo with 26 significant bits each (Veltkamp); |a| < 2^995.
[[gnu::always_inline]] inline DD split(double a) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  const double hi = c - (c - a);
  return {hi, a - hi};
}

// a·b = p + e exactly (Dekker), without fma.
[[gnu::always_inline]] inline DD two_prod(double a, double b) {
  const double p = a * b;
  const DD x = split(a), y = split(b);
  return {p, ((x.hi * y.hi - p) + x.hi * y.lo + x.lo * y.hi) + x.lo * y.lo};
}

// a² = p + e exactly.
[[gnu::always_inline]] inline DD two_sqr(double a) {
  const double p = a * a;
  const DD x = split(a);
  return {p, ((x.hi * x.hi - p) + 2.0 * (x.hi * x.lo)) + x.lo * x.lo};
}

// s + b, the rounding error of the leading sum kept in the tail.
[[gnu::always_inline]] inline DD add(DD s, double b) {
  const DD t = two_sum(s.hi, b);
  return {t.hi, s.lo + t.lo};
}

// (n.hi + n.lo) / (d.hi + d.lo) to about 2^-100 relative, one long division step.
[[gnu::always_inline]] inline DD div(DD n, DD d) {
  const double q = n.hi / d.hi;
  const DD p = two_prod(q, d.hi);
  const double rem = (((n.hi - p.hi) - p.lo) + n.lo) - q * d.lo;
  return fast_two_sum(q, rem / d.hi);
}

// ---- exp ------------------------------------------------------------------------------------

constexpr double inv_ln2 = 0x1.71547652b82fep+0;
constexpr double ln2_hi = 0x1.62e42fefa3800p-1;  // 42 bits: k·ln2_hi is exact for |k| < 2^11
constexpr double ln2_lo = 0x1.ef35793c76730p-45;

// (e^r − 1 − r − r²/2)/r³ on |r| ≤ ln2/2, error < 1e-19.
[[gnu::always_inline]] inline double exp_q(double r) {
  return horner(r, 0x1.5555555555555p-3, 0x1.5555555555556p-5, 0x1.1111111111112p-7,
                0x1.6c16c16c162d6p-10, 0x1.a01a01a019231p-13, 0x1.a01a01a6d7954p-16,
                0x1.71de3a5c49776p-19, 0x1.27e4db6779b6ep-22, 0x1.ae6424c0000e2p-26,
                0x1.1f72fce0f97c9p-29, 0x1.61cc95babcc56p-33);
}

// e^(x + xl) = 2^k·m, m = e^r in [0.7, 1.42] as a double-double (~2^-59 relative), for
// |x| ≤ 746 (xl: the tail of a double-double argument, from pow). x = k·ln2 + r with r a
// double-double; 1 + r + r²/2 is summed exactly, so that only r³·Q(r) is rounded before m.hi.
struct ExpParts {
  double k;
  DD m;
};
[[gnu::always_inline]] inline ExpParts exp_parts(double x, double xl) {
  const double k = round_int(x * inv_ln2);
  const double hi = x - k * ln2_hi;  // exact (Sterbenz)
  const double lo = k * ln2_lo - xl;
  const DD r = two_sum(hi, -lo);
  const DD r2 = two_sqr(r.hi);
  const DD one_r = fast_two_sum(1.0, r.hi);
  const DD s = fast_two_sum(one_r.hi, 0.5 * r2.hi);
  const double cubic = r2.hi * r.hi * exp_q(r.hi);
  // e^(r + δ) ≈ e^r·(1 + δ), δ = r.lo
  const double tail = (one_r.lo + s.lo) + ((0.5 * r2.lo + cubic) + (r.lo + r.lo * r.hi));
  return {k, fast_two_sum(s.hi, tail)};
}

// e^(x + xl), overflow to +inf and underflow to 0 by the clamp (e^-746 rounds to 0).
[[gnu::always_inline]] inline double exp_dd(double x, double xl) {
  const double xc = select(x > 710.0, 710.0, select(x < -746.0, -746.0, x));  // NaN stays
  const ExpParts e = exp_parts(xc, xl);
  return canonical(scale(e.m.hi, e.k));
}

// e^a/2 and e^−a/2 as double-doubles for 0 ≤ a ≤ 711, for sinh, cosh, tanh: the halving is
// folded into the exponent, so nothing overflows before the result does.
struct HalfExps {
  DD up, down;
};
[[gnu::always_inline]] inline HalfExps half_exps(double a) {
  const ExpParts e = exp_parts(a, 0.0);
  const double q = 1.0 / e.m.hi;
  const DD qm = two_prod(q, e.m.hi);
  const double ql = q * (((1.0 - qm.hi) - qm.lo) - q * e.m.lo);  // 1/m = q·(1 + residual)
  const double k1 = round_int(0.5 * (e.k - 1.0)), k2 = e.k - 1.0 - k1;
  const double u1 = pow2(k1), u2 = pow2(k2), d1 = pow2(-k1), d2 = pow2(-k2 - 2.0);
  return {{(e.m.hi * u1) * u2, (e.m.lo * u1) * u2}, {(q * d1) * d2, (ql * d1) * d2}};
}

// ---- log ------------------------------------------------------------------------------------

// x = 2^k·m with m in [√2/2, √2), for finite x > 0 (subnormals scaled up first).
struct LogParts {
  double k, m;
};
[[gnu::always_inline]] inline LogParts log_parts(double x) {
  const bool sub = x < 0x1p-1022;
  u64 u = bits(select(sub, x * 0x1p54, x));
  // Adding the distance from 1 to √2/2 makes the exponent field step at √2 instead of at 2.
  u += 0x3ff0000000000000 - 0x3fe6a09e667f3bcd;
  const double e = from_bits((u >> 52) | 0x4330000000000000) - 0x1p52;  // biased exponent, exact
  const double m = from_bits((u & 0x000fffffffffffff) + 0x3fe6a09e667f3bcd);
  return {e - select(sub, 1023.0 + 54.0, 1023.0), m};
}

// log((1+s)/(1−s)) = 2s + s·R(s²), R(z) = z·g(z), on z ≤ 0.0295 (|g error| < 3e-20).
[[gnu::always_inline]] inline double log_r(double z) {
  return z * horner(z, 0x1.5555555555555p-1, 0x1.9999999999a39p-2, 0x1.2492492476948p-2,
                    0x1.c71c7201b2b17p-3, 0x1.745cf8e290d22p-3, 0x1.3b1c3bf8b4d9ap-3,
                    0x1.0fbdf248413a0p-3, 0x1.0c09d0470566bp-3);
}

// log(x) for finite x > 0 as a double-double (error below 2^-63 relative, the limit of the
// long double check), for pow:
// log m = 2s + (2/3)s³ + s⁵·T(s²) with s = (m−1)/(m+1), the first two terms in double-double.
[[gnu::always_inline]] inline DD log_dd(double x) {
  const LogParts lp = log_parts(x);
  const DD s = div({lp.m - 1.0, 0.0}, two_sum(lp.m, 1.0));  // m − 1 is exact
  const DD s2 = two_prod(s.hi, s.hi);
  const DD s3 = two_prod(s2.hi, s.hi);
  const double s3_lo = s3.lo + s2.lo * s.hi + 3.0 * (s2.hi * s.lo);
  constexpr double c23_hi = 0x1.5555555555555p-1, c23_lo = 0x1.5555555555555p-55;  // 2/3
  const DD b = two_prod(c23_hi, s3.hi);
  const double b_lo = b.lo + (c23_hi * s3_lo + c23_lo * s3.hi);
  const double z = s2.hi;
  const double t = horner(z, 0x1.999999999999ap-2, 0x1.2492492492523p-2, 0x1.c71c71c6ea420p-3,
                          0x1.745d177ae104bp-3, 0x1.3b1395b5e95f2p-3, 0x1.1118cd548cbd8p-3,
                          0x1.df7bbeacad639p-4, 0x1.e038704393915p-4);
  const double c = (s3.hi * z) * t;
  DD r = two_sum(lp.k * ln2_hi, 2.0 * s.hi);  // k·ln2_hi exact
  r = add(r, b.hi);
  r.lo = r.lo + (lp.k * ln2_lo + (2.0 * s.lo + (b_lo + c)));
  return fast_two_sum(r.hi, r.lo);
}

// ---- sin, cos, tan ----------------------------------------------------------------------------

// π/2 = pio2_1 + … + pio2_5; the first four have 22 significant bits, so n·pio2_i is exact for
// |n| < 2^31, and the sum carries 141 bits.
constexpr double two_over_pi = 0x1.45f306dc9c883p-1;
constexpr double pio2_1 = 0x1.921fb80000000p+0;
constexpr double pio2_2 = -0x1.5dde980000000p-23;
constexpr double pio2_3 = 0x1.8469880000000p-48;
constexpr double pio2_4 = 0x1.8cc5180000000p-72;
constexpr double pio2_5 = -0x1.fc8f8cbb5bf6cp-97;

// x = n·π/2 + r, r a double-double with |r| ≤ π/4 (+ a hair), exact products up to
// |x| ≈ 2^31·π/2 ≈ 3.4e9.
struct Reduced {
  double n;  // integer-valued
  DD r;
};
[[gnu::always_inline]] inline Reduced reduce_pio2(double x) {
  const double n = round_int(x * two_over_pi);
  DD r = two_sum(x - n * pio2_1, -(n * pio2_2));  // x − n·pio2_1 exact (Sterbenz)
  r = add(r, -(n * pio2_3));
  r = add(r, -(n * pio2_4));
  r.lo = r.lo - n * pio2_5;
  return {n, fast_two_sum(r.hi, r.lo)};
}

// sin(r) as hi + tail for |r| ≤ π/4 (fdlibm's __kernel_sin with our coefficients):
// r + r³·S(r²) + tail·(1 − r²/2), |S error| < 2e-20.
[[gnu::always_inline]] inline DD sin_kernel(DD r) {
  const double z = r.hi * r.hi;
  const double v = z * r.hi;
  const double s = horner(z, 0x1.1111111111110p-7, -0x1.a01a01a019939p-13, 0x1.71de3a5460acbp-19,
                          -0x1.ae645412e9478p-26, 0x1.61217f254d0dap-33, -0x1.ab17e1eceb522p-41);
  const double tail = -(((z * (0.5 * r.lo - v * s) - r.lo) - v * -0x1.5555555555555p-3));
  return {r.hi, tail};
}

// cos(r) as hi + tail for |r| ≤ π/4 (fdlibm's __kernel_cos): 1 − r²/2 with r² exact and the
// rounding error of the difference carried, then + r⁴·C(r²), |C error| < 1e-21.
[[gnu::always_inline]] inline DD cos_kernel(DD r) {
  const DD zz = two_sqr(r.hi);
  const double z = zz.hi;
  const double c = horner(z, 0x1.5555555555555p-5, -0x1.6c16c16c16c16p-10, 0x1.a01a01a019d0bp-16,
                          -0x1.27e4fb7712df8p-22, 0x1.1eed8deba5fdap-29, -0x1.9394ba216db0fp-37,
                          0x1.ab786618ca59ap-45);
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  return {w, ((1.0 - w) - hz) + (z * (z * c) - (r.hi * r.lo + 0.5 * zz.lo))};
}

// Beyond |n| = 2^31 the products n·pio2_i stop being exact and the reduced argument loses most
// of its digits at once (there is no Payne–Hanek reduction here): NaN rather than a wrong number.
constexpr double trig_max = 3.37e9;  // < (2^31 − 1)·π/2

struct SinCos {
  double sin, cos;
};
[[gnu::always_inline]] inline SinCos sincos(double x) {
  const Reduced red = reduce_pio2(x);
  const DD s = sin_kernel(red.r), c = cos_kernel(red.r);
  const double sv = s.hi + s.lo, cv = c.hi + c.lo;
  // Quadrant n mod 4 from the low bits of n + 1.5·2^52; sin(r + nπ/2) cycles sin, cos, −sin, −cos.
  const u64 q = bits(red.n + round_shift);
  const bool odd = (q & 1) != 0;
  const double sin_abs = select(odd, cv, sv), cos_abs = select(odd, sv, cv);
  const double sin_v = from_bits(bits(sin_abs) ^ ((q & 2) << 62));
  const double cos_v = from_bits(bits(cos_abs) ^ (((q + 1) & 2) << 62));
  const double a = std::fabs(x);
  // sin x rounds to x below 2^-27; returning x keeps −0 and subnormals.
  return {select(a < 0x1p-27, x, select(a < trig_max, sin_v, nan)),
          select(a < trig_max, cos_v, nan)};
}

}  // namespace detail

// ---- public functions -------------------------------------------------------------------------

[[gnu::always_inline]] inline double sqrt(double x) { return std::sqrt(x); }  // IEEE-exact
[[gnu::always_inline]] inline double abs(double x) { return std::fabs(x); }

// e^x: +inf above 709.78, +0 below −745.13, NaN for NaN.
[[gnu::always_inline]] inline double exp(double x) { return detail::exp_dd(x, 0.0); }

// log x: −inf at ±0, NaN below 0 and for NaN, +inf at +inf; subnormals exact-scaled.
// fdlibm's formulation: log(1+f) = f − f²/2 + s·(f²/2 + R(s²)), s = f/(2+f).
[[gnu::always_inline]] inline double log(double x) {
  using namespace detail;
  const LogParts lp = log_parts(x);
  const double f = lp.m - 1.0;  // exact
  const double s = f / (2.0 + f);
  const double hfsq = 0.5 * (f * f);
  const double r = log_r(s * s);
  const double y = lp.k * ln2_hi - ((hfsq - (s * (hfsq + r) + lp.k * ln2_lo)) - f);
  const double special = select(x == inf, inf, select(x == 0.0, -inf, nan));
  return select(x > 0.0, select(x < inf, y, special), special);
}

// sin, cos: Cody–Waite reduction by π/2 in five parts to a double-double argument, exact for
// |x| < 3.37e9 (n < 2^31). Beyond that, without a Payne–Hanek reduction, most digits would be
// lost at once: NaN for |x| ≥ 3.37e9, as for ±inf and NaN.
[[gnu::always_inline]] inline double sin(double x) { return detail::sincos(x).sin; }
[[gnu::always_inline]] inline double cos(double x) { return detail::sincos(x).cos; }

// tan = sin r / cos r (or −cos r / sin r in odd quadrants), divided in double-double so that
// only the last rounding counts. Same range as sin.
[[gnu::always_inline]] inline double tan(double x) {
  using namespace detail;
  const Reduced red = reduce_pio2(x);
  const DD sk = sin_kernel(red.r), ck = cos_kernel(red.r);
  const DD s = fast_two_sum(sk.hi, sk.lo), c = fast_two_sum(ck.hi, ck.lo);
  const bool odd = (bits(red.n + round_shift) & 1) != 0;
  const DD num = {select(odd, c.hi, s.hi), select(odd, c.lo, s.lo)};
  const DD den = {select(odd, -s.hi, c.hi), select(odd, -s.lo, c.lo)};
  const DD t = div(num, den);
  const double a = std::fabs(x);
  return select(a < 0x1p-27, x, select(a < trig_max, t.hi + t.lo, nan));
}

// sinh, cosh, tanh from e^a/2 ± e^−a/2 (a = |x|) in double-double: the parts of e^a are accurate
// to ~2^-59 relative, so even the cancellation in sinh for small a costs no more than ~0.1 ulp
// and no polynomial for small arguments is needed; |x| < 2^-27 returns x (sinh, tanh), which
// keeps −0 and subnormals exact. The halving is folded into the exponent: sinh and cosh overflow
// only where they do (|x| > 710.48); tanh clamps a at 20, where it is ±1.
[[gnu::always_inline]] inline double sinh(double x) {
  using namespace detail;
  const double a = std::fabs(x);
  const HalfExps e = half_exps(select(a > 711.0, 711.0, a));
  const DD d = two_sum(e.up.hi, -e.down.hi);
  const double y = select(e.up.hi == inf, inf, d.hi + (d.lo + (e.up.lo - e.down.lo)));
  return canonical(select(a < 0x1p-27, x, copysign(y, x)));
}

[[gnu::always_inline]] inline double cosh(double x) {
  using namespace detail;
  const double a = std::fabs(x);
  const HalfExps e = half_exps(select(a > 711.0, 711.0, a));
  const DD d = two_sum(e.up.hi, e.down.hi);
  return canonical(select(e.up.hi == inf, inf, d.hi + (d.lo + (e.up.lo + e.down.lo))));
}

[[gnu::always_inline]] inline double tanh(double x) {
  using namespace detail;
  const double a = std::fabs(x);
  const HalfExps e = half_exps(select(a > 20.0, 20.0, a));
  const DD sh = two_sum(e.up.hi, -e.down.hi), ch = two_sum(e.up.hi, e.down.hi);
  const DD t = div(fast_two_sum(sh.hi, sh.lo + (e.up.lo - e.down.lo)),
                   fast_two_sum(ch.hi, ch.lo + (e.up.lo + e.down.lo)));
  return canonical(select(a < 0x1p-27, x, copysign(t.hi + t.lo, x)));
}

namespace detail {

// asin(√z)/√z − 1 = z·R(z) on z ≤ 1/4 (|R error| < 6e-20).
[[gnu::always_inline]] inline double asin_r(double z) {
  return z * horner(z, 0x1.5555555555555p-3, 0x1.333333333332cp-4, 0x1.6db6db6db7e25p-5,
                    0x1.f1c71c70d92c4p-6, 0x1.6e8ba3210b6e4p-6, 0x1.1c4ebce9222e4p-6,
                    0x1.c99b15889a849p-7, 0x1.7a6f7d996fa27p-7, 0x1.40f004f6e2bc4p-7,
                    0x1.0a42166af40e4p-7, 0x1.21d3ec8e23752p-7, 0x1.c2b4e58035816p-13,
                    0x1.776fa01f90042p-6, -0x1.91234ba7d15ddp-6, 0x1.fba2c8f170617p-6);
}

constexpr double pio2_hi = 0x1.921fb54442d18p+0;
constexpr double pio2_lo = 0x1.1a62633145c07p-54;
constexpr double pio4_hi = 0x1.921fb54442d18p-1;

// √z = f + c with f the leading 21 bits of s = √z (f² exact) and c its correction.
[[gnu::always_inline]] inline DD sqrt_split(double z, double s) {
  const double f = from_bits(bits(s) & 0xffffffff00000000);
  return {f, (z - f * f) / select(s > 0.0, s + f, 1.0)};  // z = 0 at |x| = 1: c = 0
}

}  // namespace detail

// asin (fdlibm's formulation): |x| < 1/2: x + x·R(x²); else π/2 − 2·asin(√((1−|x|)/2)) with the
// square root split in two. NaN for |x| > 1 (from the square root) and NaN.
[[gnu::always_inline]] inline double asin(double x) {
  using namespace detail;
  const double a = std::fabs(x);
  const bool near0 = a < 0.5;
  const double z = select(near0, a * a, 0.5 * (1.0 - a));  // 1 − a exact
  const double r = asin_r(z);
  const double s = std::sqrt(z);
  const DD f = sqrt_split(z, s);
  const double far = pio4_hi - ((2.0 * s * r - (pio2_lo - 2.0 * f.lo)) - (pio4_hi - 2.0 * f.hi));
  return canonical(copysign(select(near0, a + a * r, far), x));
}

// acos (fdlibm): |x| < 1/2: π/2 − (x + x·R(x²)); x ≤ −1/2: π − 2·asin(√((1+x)/2));
// x ≥ 1/2: 2·asin(√((1−x)/2)); the square root split in both.
// NaN for |x| > 1 and NaN.
[[gnu::always_inline]] inline double acos(double x) {
  using namespace detail;
  const double a = std::fabs(x);
  const bool near0 = a < 0.5;
  const double z = select(near0, x * x, 0.5 * (1.0 - a));
  const double r = asin_r(z);
  const double s = std::sqrt(z);
  const DD f = sqrt_split(z, s);
  const double mid = pio2_hi - (x - (pio2_lo - x * r));
  const double pi_2f = 0x1.921fb54442d18p+1 - 2.0 * f.hi;  // exact
  const double neg = pi_2f - 2.0 * ((r * s + f.lo) - pio2_lo);
  const double pos = 2.0 * (f.hi + (r * s + f.lo));
  return canonical(select(near0, mid, select(x < 0.0, neg, pos)));
}

// atan (fdlibm): |x| is reduced to |t| ≤ 7/16 around 0, 1/2, 1, 3/2 or ∞ by
// atan a = atan c + atan((a − c)/(1 + a·c)), then t + t³·A(t²). Full range, ±π/2 at ±inf.
[[gnu::always_inline]] inline double atan(double x) {
  using namespace detail;
  const double a = std::fabs(x);
  // t = (a·mul − c)/(mul + a·c) with atan c = hi + lo: from 7/16 on (2a−1)/(2+a), from 11/16
  // (a−1)/(a+1), from 19/16 (a−1.5)/(1+1.5a), from 39/16 −1/a; the numerators are exact.
  const bool i1 = a >= 0x1.cp-2, i2 = a >= 0x1.6p-1, i3 = a >= 0x1.3p+0, far = a >= 0x1.38p+1;
  const double mul = select(i2, 1.0, select(i1, 2.0, 1.0));
  const double c = select(i3, 1.5, select(i1, 1.0, 0.0));
  const double hi =
      select(far, 0x1.921fb54442d18p+0,
             select(i3, 0x1.f730bd281f69bp-1,
                    select(i2, 0x1.921fb54442d18p-1, select(i1, 0x1.dac670561bb4fp-2, 0.0))));
  const double lo =
      select(far, 0x1.1a62633145c07p-54,
             select(i3, 0x1.007887af0cbbdp-56,
                    select(i2, 0x1.1a62633145c07p-55, select(i1, 0x1.a2b7f222f65e2p-56, 0.0))));
  const double num = select(far, -1.0, a * mul - c);
  const double den = select(far, a, mul + a * c);
  const double t = num / den;
  const double z = t * t;
  const double q =
      t * (z * horner(z, -0x1.5555555555555p-2, 0x1.9999999999990p-3, -0x1.249249249198ep-3,
                      0x1.c71c71c67be75p-4, -0x1.745d171fc9deep-4, 0x1.3b13abdbe1674p-4,
                      -0x1.111093ffc988fp-4, 0x1.e1d2912474b65p-5, -0x1.ae82dfe757426p-5,
                      0x1.813c67cf1558dp-5, -0x1.4af5bb1c77534p-5, 0x1.debe0e1648687p-6,
                      -0x1.9b830efd822f2p-7));
  return canonical(copysign(hi + ((q + lo) + t), x));
}

// x^y = e^(y·log x), with log x in double-double and the product y·log x exact to ~2^-100, so
// that the result stays within an ulp even where y·log x is large. Conventions: y = 0 or x = 1
// gives 1 (also for NaN); x < 0 gives NaN whatever y (even integer y: std::pow differs there);
// x = ±0 gives +0 for y > 0 and +inf for y < 0 (no signed zeros or infinities); x = +inf gives
// +inf for y > 0 and +0 for y < 0; |y·log x| large gives +inf or +0.
[[gnu::always_inline]] inline double pow(double x, double y) {
  using namespace detail;
  const double xf = select(x < inf, x, -1.0);  // finite x > 0 ⟺ xf > 0
  const DD lx = log_dd(select(xf > 0.0, xf, 1.0));
  const double lx_special = select(x == inf, inf, select(x == 0.0, -inf, nan));
  const double t = y * select(xf > 0.0, lx.hi, lx_special);
  const bool regular = select(xf > 0.0, std::fabs(t), nan) < 1000.0;  // false for NaN
  const double ys = select(regular, y, 0.0);                          // keeps the splits finite
  const DD p = two_prod(ys, lx.hi);
  const double general = exp_dd(p.hi, p.lo + ys * lx.lo);
  const double beyond = select(t == t, select(t > 0.0, inf, 0.0), nan);
  return select(y == 0.0, 1.0, select(x == 1.0, 1.0, select(regular, general, beyond)));
}

}  // namespace cs::lane_math
