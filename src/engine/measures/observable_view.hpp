// What a measure written as a formula reads ([measures] observe, stop; docs/observables.md): the
// view of one lane that the generated struct (formula/measure_formulas.hpp, measures_source)
// reads through q<i>(x), p<i>(x), z(x), t(x), lambda(x). Apart from the tracker that keeps their
// statistics (observables.hpp), so that a step kernel (engine/step_kernel_entry.hpp) can hold the
// formulas without the block runner.
#pragma once

namespace cs {

// What a measure's formula reads: one lane's state, its time and λ = exp(ln λ).
template <int D>
struct ObservableView {
  const double* q;
  const double* p;
  double z, t, lambda;
};
template <int i, int D>
inline double q(const ObservableView<D>& x) { return x.q[i]; }
template <int i, int D>
inline double p(const ObservableView<D>& x) { return x.p[i]; }
template <int D>
inline double z(const ObservableView<D>& x) { return x.z; }
template <int D>
inline double t(const ObservableView<D>& x) { return x.t; }
template <int D>
inline double lambda(const ObservableView<D>& x) { return x.lambda; }

// The measures of a run without observe and stop (every built-in kernel).
struct NoMeasureFormulas {
  static constexpr int observables = 0;
  static constexpr bool stop = false;
  static constexpr bool reads_lambda = false;
  template <class X, class C>
  static void observe(const X&, const C&, double*) {}
  template <class X, class C>
  static bool stops(const X&, const C&) { return false; }
  template <class X, class C>
  static double exit(const X&, const C&) { return 0.0; }
};

template <class M>
inline constexpr bool kHasFormulas = M::observables > 0 || M::stop;

}  // namespace cs
