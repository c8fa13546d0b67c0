// Forward-mode dual numbers: a value and one directional derivative. A scene writes K once as a
// template over its number type; evaluating it with one input seeded gives that partial. `T` is
// a double (the tiled kernel vectorises its loop over lanes); everything is inline and branch-free, and
// terms that do not involve the seeded input stay plain numbers and cost nothing extra.
#pragma once

#include <type_traits>

namespace cs {

template <class T>
struct Dual {
  T v;  // value
  T d;  // derivative along the seeded direction
};

template <class T> constexpr Dual<T> operator+(Dual<T> a, Dual<T> b) { return {a.v + b.v, a.d + b.d}; }
template <class T> constexpr Dual<T> operator-(Dual<T> a, Dual<T> b) { return {a.v - b.v, a.d - b.d}; }
template <class T> constexpr Dual<T> operator-(Dual<T> a) { return {-a.v, -a.d}; }
template <class T> constexpr Dual<T> operator*(Dual<T> a, Dual<T> b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
template <class T> constexpr Dual<T> operator+(Dual<T> a, T c) { return {a.v + c, a.d}; }
template <class T> constexpr Dual<T> operator+(T c, Dual<T> a) { return {c + a.v, a.d}; }
template <class T> constexpr Dual<T> operator-(Dual<T> a, T c) { return {a.v - c, a.d}; }
template <class T> constexpr Dual<T> operator-(T c, Dual<T> a) { return {c - a.v, -a.d}; }
template <class T> constexpr Dual<T> operator*(Dual<T> a, T c) { return {a.v * c, a.d * c}; }
template <class T> constexpr Dual<T> operator*(T c, Dual<T> a) { return {c * a.v, c * a.d}; }
// Literal constants (0.5 * x) where T is a pack of lanes.
template <class T> requires(!std::is_same_v<T, double>)
constexpr Dual<T> operator*(double c, Dual<T> a) { return {c * a.v, c * a.d}; }
template <class T> requires(!std::is_same_v<T, double>)
constexpr Dual<T> operator+(Dual<T> a, double c) { return {a.v + c, a.d}; }
template <class T> requires(!std::is_same_v<T, double>)
constexpr Dual<T> operator-(Dual<T> a, double c) { return {a.v - c, a.d}; }
// The same on the other side, for nested duals (Dual<Dual<double>>: a tangent step evaluating
// K's partials, engine/measures/tangent_lyapunov.hpp), where `1.0 - x` and `x * 2.0` meet a
// Dual whose parts are duals themselves.
template <class T> requires(!std::is_same_v<T, double>)
constexpr Dual<T> operator*(Dual<T> a, double c) { return {a.v * c, a.d * c}; }
template <class T> requires(!std::is_same_v<T, double>)
constexpr Dual<T> operator+(double c, Dual<T> a) { return {c + a.v, a.d}; }
template <class T> requires(!std::is_same_v<T, double>)
constexpr Dual<T> operator-(double c, Dual<T> a) { return {c - a.v, -a.d}; }

// x², with the derivative 2x·x' written so that a seed of 1 costs one addition.
template <class T> constexpr T square(T x) { return x * x; }
template <class T> constexpr Dual<T> square(Dual<T> x) { return {x.v * x.v, (x.v + x.v) * x.d}; }

// x²/2, whose derivative x·x' is free when x is the seeded input: kinetic energies p²/2 then
// give K_p = p with no arithmetic at all.
template <class T> constexpr T half_square(T x) { return 0.5 * (x * x); }
template <class T> constexpr Dual<T> half_square(Dual<T> x) { return {0.5 * (x.v * x.v), x.v * x.d}; }

}  // namespace cs
