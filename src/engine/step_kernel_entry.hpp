// The kernel's side of a step kernel (step_kernel.hpp): the tables of one scene, carried state
// and parameter layout, one per fixed-step method, included only by a step kernel's generated
// source (kernel_build/kernel_source.cpp). Each entry is the scene's own template code, the code
// a whole kernel's runner would have inlined: the same bits.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string_view>

#include "engine/lane_health.hpp"
#include "engine/lane_tile.hpp"
#include "engine/measures/formula_steps.hpp"
#include "engine/measures/observable_view.hpp"
#include "engine/proxy_scene.hpp"
#include "engine/step_kernel.hpp"
#include "numerics/lane_state.hpp"
#include "numerics/method_list.hpp"
#include "physics/energy_wells.hpp"
#include "physics/partials.hpp"

namespace cs {

// The scene's per-lane functions, the same for every method: compiled once per kernel, not once
// per method's table.
template <Scene S>
struct StepKernelScene {
  static constexpr int D = S::dof;
  using Params = ParamsOf<S, double>;
  static Params params(const double* values) {
    Params c;
    std::memcpy(&c, values, sizeof c);
    return c;
  }
  static const LaneState<D>& state(const void* x) { return *static_cast<const LaneState<D>*>(x); }

  static bool defined_at(const void* x, const double* c) {
    return cs::defined_at<S>(state(x), params(c));
  }
  static double K(const double* q, const double* p, double z, double t, const double* c) {
    return cs::K<S>(q, p, z, params(c), t);
  }
  static double log_lambda(const void* x) { return cs::log_lambda<S>(state(x)); }
  static bool diverged(const double* q, const double* p) { return S::diverged(q, p); }
  static void natural_frequencies(const double* c, double* omega) {
    cs::natural_frequencies<S>(params(c), omega);
  }
};

// The energy trap's entries (step_kernel.hpp's StepKernelTrap), for a K that has one: E as the
// runner's screen computes it in a whole kernel (EnergyTrap::flag), lane by lane over the tile;
// the wells with the scene's own code.
template <Scene S>
struct StepKernelTrapOf : StepKernelScene<S> {
  using StepKernelScene<S>::D, StepKernelScene<S>::params;
  using Params = ParamsOf<S, double>;
  using Box = BasinBox<D>;
  static void tile_energy(const double* q, const double* p, const double* fields,
                          const double* uniform, double* energy) {
    constexpr int W = kStepKernelWidth;
    if (uniform != nullptr) {
      const Params c = params(uniform);
#pragma GCC ivdep
      for (int i = 0; i < W; ++i) {
        double x[D], y[D];
        for (int d = 0; d < D; ++d) x[d] = q[d * W + i], y[d] = p[d * W + i];
        energy[i] = cs::K<S>(x, y, 0.0, c, 0.0);
      }
    } else {
      constexpr int n = static_cast<int>(sizeof(Params) / sizeof(double));
#pragma GCC ivdep
      for (int i = 0; i < W; ++i) {
        double x[D], y[D], v[n];
        for (int d = 0; d < D; ++d) x[d] = q[d * W + i], y[d] = p[d * W + i];
        for (int j = 0; j < n; ++j) v[j] = fields[j * W + i];
        energy[i] = cs::K<S>(x, y, 0.0, params(v), 0.0);
      }
    }
  }
  static double trap_potential(const double* q, const double* c) {
    return cs::trap_potential<S>(q, params(c));
  }
  static void trap_box(const double* c, const void* positions, const double* widen, double e0,
                       double h, void* box) {
    std::array<double, D> w;
    std::copy_n(widen, D, w.begin());
    *static_cast<Box*>(box) = cs::trap_box<S>(params(c), *static_cast<const Box*>(positions), w, e0, h);
  }
  static void trap_wells(const double* c, const void* box, double h, void* wells) {
    *static_cast<Wells<D>*>(wells) = cs::trap_wells<S>(params(c), *static_cast<const Box*>(box), h);
  }
  static bool well_bottom(const double* c, const void* box, double h, const double* q,
                          const void* wells, double* minimum) {
    std::array<double, D> m;
    if (!cs::well_bottom<S>(params(c), *static_cast<const Box*>(box), h, q,
                            *static_cast<const Wells<D>*>(wells), m))
      return false;
    std::copy_n(m.begin(), D, minimum);
    return true;
  }

  static constexpr StepKernelTrap table{true, &tile_energy, &trap_potential, &trap_box, &trap_wells,
                                        &well_bottom};
};

// The trap's entries where the kernel is built with them (Trap) and K has one; else none.
template <Scene S, bool Trap>
constexpr StepKernelTrap step_kernel_trap() {
  if constexpr (Trap && has_energy_trap<S>()) return StepKernelTrapOf<S>::table;
  else return StepKernelTrap{};
}

// The run's measures as formulas (step_kernel.hpp's StepKernelFormulas), where the kernel is
// built with them (M, the generated struct); else none. The runner keeps their every-step state
// for kStepKernelMaxObservables.
template <int W>
using StepKernelFormulaSteps = FormulaSteps<kStepKernelMaxObservables, W>;

template <Scene S, class M>
struct StepKernelFormulasOf {
  static constexpr int D = S::dof;
  static_assert(M::observables <= kStepKernelMaxObservables);
  static ObservableView<D> view(const double* q, const double* p, double z, double t,
                                double lambda) {
    return {q, p, z, t, lambda};
  }
  static void observe(const double* q, const double* p, double z, double t, double lambda,
                      const double* c, double* values) {
    M::observe(view(q, p, z, t, lambda), StepKernelScene<S>::params(c), values);
  }
  static bool stops(const double* q, const double* p, double z, double t, double lambda,
                    const double* c) {
    return M::stops(view(q, p, z, t, lambda), StepKernelScene<S>::params(c));
  }
  static double exit(const double* q, const double* p, double z, double t, double lambda,
                     const double* c) {
    return M::exit(view(q, p, z, t, lambda), StepKernelScene<S>::params(c));
  }
  static constexpr StepKernelFormulas table() {
    if constexpr (kHasFormulas<M>)
      return {M::observables, M::stop, M::reads_lambda,
              sizeof(StepKernelFormulaSteps<kStepKernelWidth>), &observe, &stops, &exit};
    else return {};
  }
};

// The table of one method: its step loop, a lane's start and coefficients; the scene's functions.
template <Scene S, class Method, Carry carry, bool Uniform, bool Trap, class M>
struct StepKernelOf : StepKernelScene<S> {
  using SceneParts = StepKernelScene<S>;
  using SceneParts::D, SceneParts::params, SceneParts::state;
  using Params = ParamsOf<S, double>;
  using Coef = typename Method::template Coef<double>;
  using Tile = LaneTile<S, Method, kStepKernelWidth, kStepKernelParamFields, kStepKernelCoefFields>;
  static constexpr int kParamFields = static_cast<int>(sizeof(Params) / sizeof(double));
  static constexpr int kCoefFields = static_cast<int>(sizeof(Coef) / sizeof(double));
  static_assert(D <= kStepKernelMaxDof && kParamFields <= kStepKernelParamFields &&
                kCoefFields <= kStepKernelCoefFields && !adaptive_method<Method>());
  // The program's tile, field for field (its proxy scene's, with the same room).
  static_assert(sizeof(Tile) == sizeof(LaneTile<ProxyScene<D>, ProxyMethod, kStepKernelWidth>));

  static LaneState<D>& state(void* x) { return *static_cast<LaneState<D>*>(x); }

  static void advance(void* tile, int steps, const double* uniform_params,
                      const double* uniform_coef, double t_start, double h) {
    Coef k;
    std::memcpy(&k, uniform_coef, sizeof k);
    cs::advance<S, Method, carry, Uniform>(*static_cast<Tile*>(tile), steps, params(uniform_params),
                                           k, t_start, h, [](int) {});
  }
  static void advance_watched(void* tile, int steps, const double* uniform_params,
                              const double* uniform_coef, double t_start, double h, int which,
                              void* steps_state) {
    Coef k;
    std::memcpy(&k, uniform_coef, sizeof k);
    Tile& t = *static_cast<Tile*>(tile);
    const Params c = params(uniform_params);
    auto& a = *static_cast<StepKernelFormulaSteps<kStepKernelWidth>*>(steps_state);
    cs::advance<S, Method, carry, Uniform>(t, steps, c, k, t_start, h, [&](int s) {
      formula_after_step<S, carry, Uniform, M>(t, which, s, a, LaneClock{t_start, h}, c);
    });
  }
  static void step(void* x, const double* c, const double* coef) {
    Coef k;
    std::memcpy(&k, coef, sizeof k);
    Method::template step<S, carry>(state(x), params(c), k);
  }
  // Compiled where the run has formulas (a step loop's second copy), the lane's step where it
  // has a stop.
  static constexpr auto advance_watched_entry() {
    if constexpr (kHasFormulas<M>) return &advance_watched;
    else return decltype(&advance_watched){nullptr};
  }
  static constexpr auto step_entry() {
    if constexpr (M::stop) return &step;
    else return decltype(&step){nullptr};
  }
  static void start(void* x, const double* c) { Method::template start<S>(state(x), params(c)); }
  static void coefficients(double h, const double* c, const void* x, double* out) {
    const Coef k = Method::template coefficients<S>(h, params(c), state(x));
    std::memcpy(out, &k, sizeof k);
  }
  static bool breaks_down(const double* coef) {
    Coef k;
    std::memcpy(&k, coef, sizeof k);
    return Method::template breaks_down<S>(k);
  }

  static constexpr StepKernel table{kStepKernelAbi, Method::description.name.data(), D,
                                    kParamFields, kCoefFields, sizeof(Tile),
                                    S::kz_constant, time_dependent<S>(),
                                    carry.z || S::z_feeds_back, carry.mu,
                                    &advance, advance_watched_entry(), step_entry(),
                                    &start, &coefficients, &breaks_down,
                                    &SceneParts::defined_at, &SceneParts::K, &SceneParts::log_lambda,
                                    &SceneParts::diverged, &SceneParts::natural_frequencies,
                                    step_kernel_trap<S, Trap>(),
                                    StepKernelFormulasOf<S, M>::table()};
};

// The table of the fixed-step method named `method` for scene S (StepKernelEntry): every one
// whose coefficients fit the tile is compiled, so a second method of the same K needs no compile.
template <Scene S, Carry carry, bool Uniform, bool Trap, class M = NoMeasureFormulas>
const StepKernel* step_kernel_of(const char* method) {
  const StepKernel* table = nullptr;
  Methods::with_named(std::string_view(method), [&]<class Method>() {
    constexpr bool fits = sizeof(typename Method::template Coef<double>) <=
                          kStepKernelCoefFields * sizeof(double);
    if constexpr (!adaptive_method<Method>() && fits)
      table = &StepKernelOf<S, Method, carry, Uniform, Trap, M>::table;
  });
  return table;
}

}  // namespace cs
