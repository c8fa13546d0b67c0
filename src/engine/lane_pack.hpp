// A pack of lanes: N doubles as one GCC/Clang vector. Wider than a hardware register on purpose:
// the compiler splits a 32-lane pack into four AVX-512 (or eight AVX2) operations that do not
// depend on each other, which hides the latency of the integrator's long dependency chain.
// Element-wise IEEE arithmetic, so a lane computes the same bits as the scalar code.
#pragma once

namespace cs {

template <int N>
struct PackOf {
  typedef double type __attribute__((vector_size(N * sizeof(double))));
};

template <int N>
using Pack = typename PackOf<N>::type;

}  // namespace cs
