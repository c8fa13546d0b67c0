// numerics/lane_math.hpp and physics/dual_math.hpp: accuracy in ulps against long double, special
// values, the same bits from the vectorised lane loop as from one call at a time (and as in every
// other build: a checksum of the bits), and the chain rule of the dual-number overloads.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>  // ::sin and friends are visible here, as in a generated scene
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "physics/dual_math.hpp"

namespace cs {
namespace {

namespace lm = lane_math;
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// ---- inputs: made from the raw bits of std::mt19937_64 with exact operations only, so that they
// are the same everywhere (std::uniform_real_distribution is not specified bit for bit).

struct Inputs {
  std::mt19937_64 rng{20240611};
  double unit() { return static_cast<double>(rng() >> 11) * 0x1p-53; }  // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * unit(); }
  // |x| log-uniform in [2^e0, 2^e1) (random binade, random mantissa), random sign if asked.
  double log_uniform(int e0, int e1, bool sign = false) {
    const auto e = static_cast<int>(rng() % static_cast<std::uint64_t>(e1 - e0));
    const double x = std::ldexp(1.0 + unit(), e0 + e);
    return sign && (rng() & 1) ? -x : x;
  }
};

// Error of got in units of the last place of the double nearest to ref.
long double ulp_error(double got, long double ref) {
  if (std::isnan(ref)) return std::isnan(got) ? 0.0L : inf;
  const double rounded = static_cast<double>(ref);  // ±inf beyond the double range
  if (std::isinf(rounded) || std::isinf(got)) return got == rounded ? 0.0L : inf;
  int e;
  std::frexp(std::fabs(ref), &e);  // |ref| in [2^(e−1), 2^e)
  const long double ulp = std::ldexp(1.0L, std::max(e - 53, -1074));
  return std::fabs(static_cast<long double>(got) - ref) / ulp;
}

// ---- accuracy ---------------------------------------------------------------------------------

struct AccuracyCase {
  std::string name;
  double (*f)(double);
  long double (*ref)(long double);
  double (*gen)(Inputs&);
  double measured;  // the largest error in ulps on these inputs, when last measured
};

void PrintTo(const AccuracyCase& c, std::ostream* os) { *os << c.name; }

class Accuracy : public ::testing::TestWithParam<AccuracyCase> {};

TEST_P(Accuracy, MaxUlpWithinMeasuredBound) {
  const AccuracyCase& c = GetParam();
  Inputs in;
  long double worst = 0;
  double worst_x = 0;
  for (int i = 0; i < 100000; ++i) {
    const double x = c.gen(in);
    const long double e = ulp_error(c.f(x), c.ref(x));
    if (!(e <= worst)) worst = e, worst_x = x;
  }
  RecordProperty("max_ulp", std::to_string(static_cast<double>(worst)));
  EXPECT_LE(worst, c.measured + 0.05)
      << c.name << ": " << static_cast<double>(worst) << " ulp at x = " << std::hexfloat << worst_x;
}

long double ref_exp(long double x) { return std::exp(x); }
long double ref_log(long double x) { return std::log(x); }
long double ref_sin(long double x) { return std::sin(x); }
long double ref_cos(long double x) { return std::cos(x); }
long double ref_tan(long double x) { return std::tan(x); }
long double ref_sinh(long double x) { return std::sinh(x); }
long double ref_cosh(long double x) { return std::cosh(x); }
long double ref_tanh(long double x) { return std::tanh(x); }
long double ref_asin(long double x) { return std::asin(x); }
long double ref_acos(long double x) { return std::acos(x); }
long double ref_atan(long double x) { return std::atan(x); }
[[gnu::always_inline]] inline double f_exp(double x) { return lm::exp(x); }
[[gnu::always_inline]] inline double f_log(double x) { return lm::log(x); }
[[gnu::always_inline]] inline double f_sin(double x) { return lm::sin(x); }
[[gnu::always_inline]] inline double f_cos(double x) { return lm::cos(x); }
[[gnu::always_inline]] inline double f_tan(double x) { return lm::tan(x); }
[[gnu::always_inline]] inline double f_sinh(double x) { return lm::sinh(x); }
[[gnu::always_inline]] inline double f_cosh(double x) { return lm::cosh(x); }
[[gnu::always_inline]] inline double f_tanh(double x) { return lm::tanh(x); }
[[gnu::always_inline]] inline double f_asin(double x) { return lm::asin(x); }
[[gnu::always_inline]] inline double f_acos(double x) { return lm::acos(x); }
[[gnu::always_inline]] inline double f_atan(double x) { return lm::atan(x); }

// pow along a line of x with y chosen so that y·log x (the exponent that matters) is spread
// over [−700, 700]; the case draws x, the pair is rebuilt from x and a hidden second draw.
thread_local double pow_y = 0;
[[gnu::always_inline]] inline double f_pow(double x) { return lm::pow(x, pow_y); }
long double ref_pow(long double x) { return std::pow(x, static_cast<long double>(pow_y)); }

// The largest error measured on these inputs (GCC 12, x86-64, glibc's long double functions as
// the reference); the test allows 0.05 ulp more.
const AccuracyCase accuracy_cases[] = {
    {"exp_708", f_exp, ref_exp, [](Inputs& in) { return in.uniform(-708, 708); }, 0.518},
    {"exp_1", f_exp, ref_exp, [](Inputs& in) { return in.uniform(-1, 1); }, 0.526},
    {"exp_tiny", f_exp, ref_exp, [](Inputs& in) { return in.log_uniform(-1074, -1, true); }, 0.5},
    // Subnormal results are rounded twice: up to a quarter ulp (of the subnormal) more.
    {"exp_subnormal", f_exp, ref_exp, [](Inputs& in) { return in.uniform(-745, -708.4); }, 0.75},
    {"log_all", f_log, ref_log, [](Inputs& in) { return in.log_uniform(-1022, 1024); }, 0.629},
    {"log_near_1", f_log, ref_log, [](Inputs& in) { return in.uniform(0.5, 2); }, 0.8},
    {"log_subnormal", f_log, ref_log, [](Inputs& in) { return in.log_uniform(-1074, -1022); },
     0.501},
    {"sin_10", f_sin, ref_sin, [](Inputs& in) { return in.uniform(-10, 10); }, 0.706},
    {"sin_1e6", f_sin, ref_sin, [](Inputs& in) { return in.uniform(-1e6, 1e6); }, 0.702},
    {"sin_log_3e9", f_sin, ref_sin, [](Inputs& in) { return in.log_uniform(-30, 31, true); },
     0.715},
    {"cos_10", f_cos, ref_cos, [](Inputs& in) { return in.uniform(-10, 10); }, 0.688},
    {"cos_1e6", f_cos, ref_cos, [](Inputs& in) { return in.uniform(-1e6, 1e6); }, 0.7},
    {"cos_log_3e9", f_cos, ref_cos, [](Inputs& in) { return in.log_uniform(-30, 31, true); },
     0.698},
    {"tan_10", f_tan, ref_tan, [](Inputs& in) { return in.uniform(-10, 10); }, 0.815},
    {"tan_1e6", f_tan, ref_tan, [](Inputs& in) { return in.uniform(-1e6, 1e6); }, 0.816},
    {"tan_log_3e9", f_tan, ref_tan, [](Inputs& in) { return in.log_uniform(-30, 31, true); },
     0.739},
    {"sinh_2", f_sinh, ref_sinh, [](Inputs& in) { return in.uniform(-2, 2); }, 0.558},
    {"sinh_log_1024", f_sinh, ref_sinh, [](Inputs& in) { return in.log_uniform(-30, 10, true); },
     0.561},
    {"cosh_2", f_cosh, ref_cosh, [](Inputs& in) { return in.uniform(-2, 2); }, 0.515},
    {"cosh_log_1024", f_cosh, ref_cosh, [](Inputs& in) { return in.log_uniform(-30, 10, true); },
     0.511},
    {"tanh_2", f_tanh, ref_tanh, [](Inputs& in) { return in.uniform(-2, 2); }, 0.547},
    {"tanh_log_32", f_tanh, ref_tanh, [](Inputs& in) { return in.log_uniform(-30, 5, true); },
     0.537},
    {"asin_1", f_asin, ref_asin, [](Inputs& in) { return in.uniform(-1, 1); }, 0.781},
    {"asin_log", f_asin, ref_asin, [](Inputs& in) { return in.log_uniform(-30, 0, true); }, 0.803},
    {"asin_near_1", f_asin, ref_asin, [](Inputs& in) { return 1.0 - in.log_uniform(-53, -4); },
     0.75},
    {"acos_1", f_acos, ref_acos, [](Inputs& in) { return in.uniform(-1, 1); }, 0.76},
    {"acos_log", f_acos, ref_acos, [](Inputs& in) { return in.log_uniform(-30, 0, true); }, 0.753},
    {"acos_near_m1", f_acos, ref_acos, [](Inputs& in) { return in.log_uniform(-53, -4) - 1.0; },
     0.5},
    {"atan_4", f_atan, ref_atan, [](Inputs& in) { return in.uniform(-4, 4); }, 0.751},
    {"atan_log", f_atan, ref_atan, [](Inputs& in) { return in.log_uniform(-60, 1000, true); },
     0.679},
    {"pow_y_log_x_700", f_pow, ref_pow,
     [](Inputs& in) {
       const double x = std::ldexp(1.0 + in.unit(), static_cast<int>(in.rng() % 20) - 10);
       pow_y = in.uniform(-700, 700) / static_cast<double>(std::log(static_cast<long double>(x)));
       return x;
     },
     0.849},
    {"pow_2.5", f_pow, ref_pow,
     [](Inputs& in) {
       pow_y = 2.5;
       return in.log_uniform(-60, 60);
     },
     0.519},
    {"pow_near_1", f_pow, ref_pow,
     [](Inputs& in) {
       pow_y = in.uniform(-1e8, 1e8);
       return 1.0 + in.uniform(-1e-6, 1e-6);
     },
     0.528},
};
INSTANTIATE_TEST_SUITE_P(LaneMath, Accuracy, ::testing::ValuesIn(accuracy_cases),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           for (char& ch : n)
                             if (ch == '.') ch = '_';
                           return n;
                         });

// ---- special values ---------------------------------------------------------------------------

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

TEST(LaneMathSpecial, ExpLog) {
  EXPECT_TRUE(std::isnan(lm::exp(nan)));
  EXPECT_EQ(lm::exp(inf), inf);
  EXPECT_TRUE(same_bits(lm::exp(-inf), 0.0));
  EXPECT_EQ(lm::exp(0.0), 1.0);
  EXPECT_EQ(lm::exp(-0.0), 1.0);
  EXPECT_EQ(lm::exp(709.78), std::exp(709.78));  // the last finite results
  EXPECT_EQ(lm::exp(709.79), inf);
  EXPECT_EQ(lm::exp(1e300), inf);
  EXPECT_EQ(lm::exp(-745.1), 0x1p-1074);  // the least subnormal
  EXPECT_TRUE(same_bits(lm::exp(-745.2), 0.0));
  EXPECT_TRUE(same_bits(lm::exp(-1e300), 0.0));

  EXPECT_EQ(lm::log(0.0), -inf);
  EXPECT_EQ(lm::log(-0.0), -inf);
  EXPECT_TRUE(std::isnan(lm::log(-1.0)));
  EXPECT_TRUE(std::isnan(lm::log(-inf)));
  EXPECT_TRUE(std::isnan(lm::log(nan)));
  EXPECT_EQ(lm::log(inf), inf);
  EXPECT_TRUE(same_bits(lm::log(1.0), 0.0));
  EXPECT_EQ(lm::log(0x1p-1074), static_cast<double>(std::log(0x1p-1074L)));
  EXPECT_EQ(lm::log(std::numeric_limits<double>::max()),
            std::log(std::numeric_limits<double>::max()));
}

TEST(LaneMathSpecial, Trigonometric) {
  for (double (*f)(double) : {f_sin, f_cos, f_tan}) {
    EXPECT_TRUE(std::isnan(f(nan)));
    EXPECT_TRUE(std::isnan(f(inf)));
    EXPECT_TRUE(std::isnan(f(-inf)));
    EXPECT_TRUE(std::isnan(f(1e10)));  // beyond the exact reduction: NaN, not a wrong number
    EXPECT_FALSE(std::isnan(f(3.3e9)));
  }
  EXPECT_TRUE(same_bits(lm::sin(-0.0), -0.0));
  EXPECT_TRUE(same_bits(lm::tan(-0.0), -0.0));
  EXPECT_EQ(lm::cos(0.0), 1.0);
  EXPECT_EQ(lm::sin(0x1p-1074), 0x1p-1074);
  EXPECT_EQ(lm::cos(-0.0), 1.0);
}

TEST(LaneMathSpecial, Hyperbolic) {
  EXPECT_TRUE(same_bits(lm::sinh(-0.0), -0.0));
  EXPECT_TRUE(same_bits(lm::tanh(-0.0), -0.0));
  EXPECT_EQ(lm::cosh(0.0), 1.0);
  EXPECT_EQ(lm::sinh(0x1p-1074), 0x1p-1074);
  EXPECT_EQ(lm::tanh(1e300), 1.0);
  EXPECT_EQ(lm::tanh(-inf), -1.0);
  EXPECT_EQ(lm::tanh(20.0), 1.0);
  EXPECT_EQ(lm::sinh(710.4), std::sinh(710.4));  // past exp's overflow, still finite
  EXPECT_EQ(lm::cosh(-710.4), std::cosh(710.4));
  EXPECT_EQ(lm::sinh(710.5), inf);
  EXPECT_EQ(lm::sinh(-inf), -inf);
  EXPECT_EQ(lm::cosh(-inf), inf);
  for (double (*f)(double) : {f_sinh, f_cosh, f_tanh}) EXPECT_TRUE(std::isnan(f(nan)));
}

TEST(LaneMathSpecial, InverseTrigonometric) {
  EXPECT_TRUE(same_bits(lm::asin(-0.0), -0.0));
  EXPECT_TRUE(same_bits(lm::atan(-0.0), -0.0));
  EXPECT_EQ(lm::asin(1.0), std::asin(1.0));
  EXPECT_EQ(lm::asin(-1.0), -std::asin(1.0));
  EXPECT_TRUE(same_bits(lm::acos(1.0), 0.0));
  EXPECT_EQ(lm::acos(-1.0), std::acos(-1.0));
  EXPECT_EQ(lm::atan(inf), std::atan(inf));
  EXPECT_EQ(lm::atan(-inf), -std::atan(inf));
  EXPECT_EQ(lm::atan(1e300), std::atan(1e300));
  for (double x : {1.0000000000000002, -1.5, inf, -inf, nan}) {
    EXPECT_TRUE(std::isnan(lm::asin(x))) << x;
    EXPECT_TRUE(std::isnan(lm::acos(x))) << x;
  }
  EXPECT_TRUE(std::isnan(lm::atan(nan)));
}

TEST(LaneMathSpecial, Pow) {
  EXPECT_EQ(lm::pow(2.0, 10.0), 1024.0);
  EXPECT_EQ(lm::pow(4.0, 0.5), 2.0);
  EXPECT_EQ(lm::pow(nan, 0.0), 1.0);  // y = 0 or x = 1: 1, even with a NaN
  EXPECT_EQ(lm::pow(-3.0, 0.0), 1.0);
  EXPECT_EQ(lm::pow(1.0, nan), 1.0);
  EXPECT_EQ(lm::pow(1.0, inf), 1.0);
  EXPECT_TRUE(std::isnan(lm::pow(-2.0, 2.0)));  // x < 0: NaN, also for integer y
  EXPECT_TRUE(std::isnan(lm::pow(-2.0, 0.5)));
  EXPECT_TRUE(std::isnan(lm::pow(nan, 1.0)));
  EXPECT_TRUE(std::isnan(lm::pow(2.0, nan)));
  EXPECT_TRUE(same_bits(lm::pow(0.0, 3.0), 0.0));
  EXPECT_TRUE(same_bits(lm::pow(-0.0, 3.0), 0.0));  // no signed zeros
  EXPECT_EQ(lm::pow(0.0, -1.0), inf);
  EXPECT_EQ(lm::pow(inf, 2.0), inf);
  EXPECT_TRUE(same_bits(lm::pow(inf, -2.0), 0.0));
  EXPECT_EQ(lm::pow(2.0, inf), inf);
  EXPECT_TRUE(same_bits(lm::pow(0.5, inf), 0.0));
  EXPECT_TRUE(same_bits(lm::pow(2.0, -inf), 0.0));
  EXPECT_EQ(lm::pow(10.0, 400.0), inf);
  EXPECT_TRUE(same_bits(lm::pow(10.0, -400.0), 0.0));
  EXPECT_EQ(lm::pow(2.0, 1023.5), std::pow(2.0, 1023.5));
  EXPECT_EQ(lm::pow(2.0, 1024.0), inf);
  EXPECT_EQ(lm::pow(2.0, -1074.0), 0x1p-1074);
  EXPECT_EQ(lm::pow(1e-300, 1e10), 0.0);
  EXPECT_EQ(lm::pow(1.0000001, 1e300), inf);
}

// ---- same bits on every path ------------------------------------------------------------------

// The lane loop as the kernel writes it: GCC vectorises it in an optimised build (AVX-512 or
// AVX2 with -march=native; checked with -fopt-info-vec when this was written). Debug and
// sanitizer builds run it in scalar code; the checksum below still ties them to the others.
constexpr int W = 64;
template <double (*F)(double)>
[[gnu::noinline]] void lanes(const double* __restrict in, double* __restrict out) {
#pragma GCC ivdep
  for (int i = 0; i < W; ++i) out[i] = F(in[i]);
}
template <double (*F)(double)>
[[gnu::noinline]] double one(double x) {
  return F(x);
}
// Wrappers are always_inline: a plain function around an inlined lane_math body would stay a
// call, and the loop in lanes<> scalar.
[[gnu::always_inline]] inline double f_sqrt(double x) { return lm::sqrt(x); }
[[gnu::always_inline]] inline double f_abs(double x) { return lm::abs(x); }
template <double Y>
[[gnu::always_inline]] inline double f_pow_y(double x) {
  return lm::pow(x, Y);
}
template <double X>
[[gnu::always_inline]] inline double f_pow_x(double y) {
  return lm::pow(X, y);
}
[[gnu::always_inline]] inline double f_dual_sin(double x) { return sin(Dual<double>{x, 0.75}).d; }
[[gnu::always_inline]] inline double f_dual_pow(double x) {
  return pow(Dual<double>{x, 1.0}, Dual<double>{1.5, 0.5}).d;
}

// Edge cases of every function, then values spread over the ranges that matter.
std::vector<double> bit_test_inputs() {
  // clang-format off
  std::vector<double> v = {
      0.0, -0.0, inf, -inf, nan, -nan, 0x1p-1074, -0x1p-1074, 0x1p-1022, 0x1p-27,
      0x1.fffffffffffffp-28, 1.0, -1.0, 0.5, -0.5, 0.4999999999999999, 2.0, 3.0, 0.4375, 0.6875,
      1.1875, 2.4375, 0.625, 1e-300, 1e300, -1e300, 709.78, 709.79, 710.4, 710.5, -745.1, -745.2,
      -746.0, 19.1, 20.0, 40.0, 1.5707963267948966, 3.141592653589793, 3.37e9, 3.3e9, 1e10, 1e22,
      std::numeric_limits<double>::max(), 1.0000000000000002, 0.9999999999999999};
  // clang-format on
  Inputs in;
  while (v.size() < 4096) {
    switch (v.size() % 4) {
      case 0: v.push_back(in.uniform(-4, 4)); break;
      case 1: v.push_back(in.log_uniform(-40, 30, true)); break;
      case 2: v.push_back(in.uniform(-1, 1)); break;
      default: v.push_back(in.log_uniform(-1074, 1024, true)); break;
    }
  }
  return v;
}

template <double (*F)(double)>
void expect_same_bits_on_every_path(const char* name) {
  const std::vector<double> v = bit_test_inputs();
  const int n = static_cast<int>(v.size());
  // Each value is met in several lane positions (the vectorised body, the peeled head or the
  // scalar tail the compiler may add) and alone.
  for (int shift : {0, 1, 7, 37}) {
    for (int base = 0; base < n; base += W) {
      double in[W], out[W];
      for (int i = 0; i < W; ++i) in[i] = v[(base + i + shift) % n];
      lanes<F>(in, out);
      for (int i = 0; i < W; ++i) {
        const double s = one<F>(in[i]);
        ASSERT_EQ(std::memcmp(&s, &out[i], sizeof s), 0)
            << name << "(" << std::hexfloat << in[i] << "): lane " << i << " gives " << out[i]
            << ", scalar " << s;
      }
    }
  }
}

TEST(LaneMathBits, VectorisedEqualsScalar) {
  expect_same_bits_on_every_path<f_exp>("exp");
  expect_same_bits_on_every_path<f_log>("log");
  expect_same_bits_on_every_path<f_sin>("sin");
  expect_same_bits_on_every_path<f_cos>("cos");
  expect_same_bits_on_every_path<f_tan>("tan");
  expect_same_bits_on_every_path<f_sinh>("sinh");
  expect_same_bits_on_every_path<f_cosh>("cosh");
  expect_same_bits_on_every_path<f_tanh>("tanh");
  expect_same_bits_on_every_path<f_asin>("asin");
  expect_same_bits_on_every_path<f_acos>("acos");
  expect_same_bits_on_every_path<f_atan>("atan");
  expect_same_bits_on_every_path<f_sqrt>("sqrt");
  expect_same_bits_on_every_path<f_abs>("abs");
  expect_same_bits_on_every_path<f_pow_y<2.5>>("pow(x, 2.5)");
  expect_same_bits_on_every_path<f_pow_y<-0.5>>("pow(x, -0.5)");
  expect_same_bits_on_every_path<f_pow_x<1.5>>("pow(1.5, y)");
  expect_same_bits_on_every_path<f_pow_x<0.0>>("pow(0, y)");
  expect_same_bits_on_every_path<f_dual_sin>("sin(dual).d");
  expect_same_bits_on_every_path<f_dual_pow>("pow(dual, dual).d");
}

// FNV-1a of the bits of every function on the inputs above. Every build (release, debug,
// sanitizer; AVX-512, AVX2 or SSE) must print the same: results must not depend on the machine
// a rank runs on. A deliberate change of lane_math.hpp changes it: update the constant then.
TEST(LaneMathBits, ChecksumIsTheSameInEveryBuild) {
  std::uint64_t h = 0xcbf29ce484222325;
  auto mix = [&](double r) {
    const auto b = std::bit_cast<std::uint64_t>(r);
    for (int k = 0; k < 64; k += 8) h = (h ^ ((b >> k) & 0xff)) * 0x100000001b3;
  };
  for (double x : bit_test_inputs()) {
    for (double r : {lm::exp(x), lm::log(x), lm::sin(x), lm::cos(x), lm::tan(x), lm::sinh(x),
                     lm::cosh(x), lm::tanh(x), lm::asin(x), lm::acos(x), lm::atan(x),
                     lm::pow(x, 2.5), lm::pow(1.5, x), lm::pow(x, x)})
      mix(r);
  }
  EXPECT_EQ(h, 0xd16c1a2b7d797500u) << std::hex << "checksum 0x" << h;
}

// ---- dual numbers -----------------------------------------------------------------------------

// A scene-like formula written once: unqualified calls inside namespace cs, <cmath> included.
template <class X>
auto formula(X x) {
  return sin(x) * exp(x) + cos(x) / (2.0 + tanh(x)) + pow(abs(x) + 1.0, 1.5) + sqrt(x * x + 1.0) +
         atan(x) * log(cosh(x)) - sinh(x) + asin(x / (abs(x) + 1.0)) + acos(0.5 * tanh(x)) +
         tan(0.5 * x) + pow(2.0, x) + pow(x * x + 1.0, x);
}

TEST(DualMath, UnqualifiedCallsFindLaneMath) {
  Inputs in;
  int differs_from_libm = 0;
  for (int i = 0; i < 1000; ++i) {
    const double x = in.uniform(-3, 3);
    const double want = lm::sin(x) * lm::exp(x) + lm::cos(x) / (2.0 + lm::tanh(x)) +
                        lm::pow(lm::abs(x) + 1.0, 1.5) + lm::sqrt(x * x + 1.0) +
                        lm::atan(x) * lm::log(lm::cosh(x)) - lm::sinh(x) +
                        lm::asin(x / (lm::abs(x) + 1.0)) + lm::acos(0.5 * lm::tanh(x)) +
                        lm::tan(0.5 * x) + lm::pow(2.0, x) + lm::pow(x * x + 1.0, x);
    EXPECT_TRUE(same_bits(formula(x), want)) << x;
    EXPECT_TRUE(same_bits(formula(Dual<double>{x, 0.0}).v, want)) << x;
    differs_from_libm += lm::sin(x) != std::sin(x) || lm::exp(x) != std::exp(x);
  }
  EXPECT_GT(differs_from_libm, 0);  // else the test could not tell ::sin from cs::sin
}

// d/dx of every overload against its closed form in long double, with seed 1 and a scaled seed.
struct DerivativeCase {
  const char* name;
  Dual<double> (*f)(Dual<double>);
  long double (*df)(long double);
  double lo, hi;
  double floor = 0;  // absolute scale where the derivative passes through 0 by cancellation
};

TEST(DualMath, ChainRuleMatchesClosedForms) {
  using L = long double;
  const DerivativeCase cases[] = {
      {"sin", [](Dual<double> x) { return sin(x); }, [](L x) { return std::cos(x); }, -10, 10},
      {"cos", [](Dual<double> x) { return cos(x); }, [](L x) { return -std::sin(x); }, -10, 10},
      {"tan", [](Dual<double> x) { return tan(x); },
       [](L x) { return 1 / (std::cos(x) * std::cos(x)); }, -1.5, 1.5},
      {"exp", [](Dual<double> x) { return exp(x); }, [](L x) { return std::exp(x); }, -30, 30},
      {"log", [](Dual<double> x) { return log(x); }, [](L x) { return 1 / x; }, 1e-3, 1e3},
      {"sqrt", [](Dual<double> x) { return sqrt(x); }, [](L x) { return 0.5L / std::sqrt(x); },
       1e-3, 1e3},
      {"abs", [](Dual<double> x) { return abs(x); }, [](L x) { return x < 0 ? -1.0L : 1.0L; }, -5,
       5},
      {"sinh", [](Dual<double> x) { return sinh(x); }, [](L x) { return std::cosh(x); }, -30, 30},
      {"cosh", [](Dual<double> x) { return cosh(x); }, [](L x) { return std::sinh(x); }, -30, 30},
      {"tanh", [](Dual<double> x) { return tanh(x); },
       [](L x) { return 1 / (std::cosh(x) * std::cosh(x)); }, -30, 30},
      {"asin", [](Dual<double> x) { return asin(x); }, [](L x) { return 1 / std::sqrt(1 - x * x); },
       -0.999, 0.999},
      {"acos", [](Dual<double> x) { return acos(x); },
       [](L x) { return -1 / std::sqrt(1 - x * x); }, -0.999, 0.999},
      {"atan", [](Dual<double> x) { return atan(x); }, [](L x) { return 1 / (1 + x * x); }, -50,
       50},
      {"pow(x, 2.7)", [](Dual<double> x) { return pow(x, 2.7); },
       [](L x) { return 2.7L * std::pow(x, 1.7L); }, 1e-2, 1e2},
      {"pow(2.7, x)", [](Dual<double> x) { return pow(2.7, x); },
       [](L x) { return std::pow(2.7L, x) * std::log(2.7L); }, -30, 30},
      {"pow(x, x)", [](Dual<double> x) { return pow(x, x); },
       [](L x) { return std::pow(x, x) * (std::log(x) + 1); }, 1.5, 10},
      {"x / (1 + x^2)", [](Dual<double> x) { return x / (1.0 + x * x); },
       [](L x) { return (1 - x * x) / ((1 + x * x) * (1 + x * x)); }, -10, 10, 1.0},
      {"x / 3", [](Dual<double> x) { return x / 3.0; }, [](L) { return 1 / 3.0L; }, -10, 10},
      {"3 / x", [](Dual<double> x) { return 3.0 / x; }, [](L x) { return -3 / (x * x); }, 0.1, 10},
  };
  Inputs in;
  for (const auto& c : cases) {
    for (int i = 0; i < 2000; ++i) {
      const double x = in.uniform(c.lo, c.hi);
      const L want = c.df(x);
      for (double seed : {1.0, -0.37}) {
        const double got = c.f(Dual<double>{x, seed}).d;
        EXPECT_LE(std::fabs(got - seed * want),
                  1e-13L * std::fabs(seed) * (std::fabs(want) + c.floor))
            << c.name << " at " << x << " (seed " << seed << ")";
      }
    }
  }
}

// Derivatives where a careless formula gives NaN, and a central difference as an independent check.
TEST(DualMath, EdgeDerivativesAndFiniteDifferences) {
  EXPECT_EQ(pow(Dual<double>{0.0, 1.0}, 2.0).d, 0.0);  // y·x^(y−1), not y·x^y/x
  EXPECT_EQ(pow(Dual<double>{0.0, 1.0}, 3.0).d, 0.0);
  EXPECT_EQ(pow(Dual<double>{0.0, 1.0}, 0.0).v, 1.0);
  EXPECT_EQ(pow(Dual<double>{0.0, 1.0}, 0.0).d, 0.0);
  EXPECT_EQ(pow(0.0, Dual<double>{2.0, 1.0}).d, 0.0);  // 0^y = 0 for y > 0
  EXPECT_EQ(pow(Dual<double>{0.0, 1.0}, Dual<double>{2.0, 1.0}).d, 0.0);
  EXPECT_EQ(abs(Dual<double>{0.0, 2.0}).d, 2.0);
  EXPECT_GT(tanh(Dual<double>{25.0, 1.0}).d, 0.0);  // sech², where 1 − tanh² would be 0

  Inputs in;
  for (int i = 0; i < 1000; ++i) {
    const double x = in.uniform(-2, 2);
    const double h = 1e-5;
    const double fd = (formula(x + h) - formula(x - h)) / (2 * h);
    const double d = formula(Dual<double>{x, 1.0}).d;
    EXPECT_NEAR(d, fd, 1e-7 * std::max(1.0, std::fabs(d))) << x;
  }
}

}  // namespace
}  // namespace cs
