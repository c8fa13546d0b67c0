// The scene and method the program's block runner sees when a step kernel (step_kernel.hpp) does
// the scene's work: every member calls the kernel's table, bound to the thread for the length of
// a block (BoundStepKernel). The runner is the same template as for any scene, so a K's lanes are
// loaded, looked at, sampled and written by the same code as a built-in scene's, and the numbers
// that depend on K (the step, a lane's start, its coefficients, K itself) come from the kernel,
// which computes them with the scene's own code: the same bits as a whole kernel
// (tests/test_custom_k.sh).
//
// The runner's screen reads the scene's traits from the kernel (run_time_traits): whether K_z is
// constant (else it checks a lane's breakdown flag) and whether K reads t (else it keeps no step
// counts). ln λ comes from the kernel, which knows which form the lane carries. The tile's
// layout is the kernel's (LaneTile with the step kernel's room).
#pragma once

#include <algorithm>
#include <array>
#include <concepts>

#include "engine/lane_tile.hpp"
#include "engine/measures/observable_view.hpp"
#include "engine/step_kernel.hpp"
#include "numerics/lane_state.hpp"
#include "physics/energy_wells.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

// The step kernel of the block this thread runs, and the count of its scene's parameters.
struct StepKernelBinding {
  const StepKernel* kernel = nullptr;
  int parameters = 0;
};
inline thread_local StepKernelBinding bound_step_kernel;

inline const StepKernel& step_kernel() { return *bound_step_kernel.kernel; }

class BoundStepKernel {
 public:
  BoundStepKernel(const StepKernel& kernel, int parameters) : previous_(bound_step_kernel) {
    bound_step_kernel = {&kernel, parameters};
  }
  ~BoundStepKernel() { bound_step_kernel = previous_; }
  BoundStepKernel(const BoundStepKernel&) = delete;
  BoundStepKernel& operator=(const BoundStepKernel&) = delete;

 private:
  StepKernelBinding previous_;
};

template <int D>
struct ProxyScene {
  static constexpr int dof = D;
  static constexpr bool is_proxy = true;
  static constexpr bool z_feeds_back = false;  // read by the step loop alone, in the kernel
  // The traits the runner reads are the kernel's scene's, at run time (run_time_traits, read
  // through engine/run_traits.hpp); these are what is right for any scene where it reads them
  // at compile time. The fields a lane's step writes are the kernel's too.
  static constexpr bool kz_constant = false;
  static constexpr bool time_dependent = true;
  struct RunTimeTraits {
    bool kz_constant, time_dependent, carries_z, carries_mu;
  };
  static RunTimeTraits run_time_traits() {
    const StepKernel& k = step_kernel();
    return {k.kz_constant, k.time_dependent, k.carries_z, k.carries_mu};
  }

  template <class T>
  struct Params {
    T v[kStepKernelParamFields];
    static int used_fields() { return step_kernel().param_fields; }  // LaneTile moves these
  };
  // The scene's parameters from `values` (its own count of them), the rest of the room zero.
  template <class T>
  static Params<T> params_from(const T* values) {
    Params<T> c{};
    std::copy_n(values, bound_step_kernel.parameters, c.v);
    return c;
  }
  // K at a state; the runner asks for no partial of it (the kernel's defined_at and the
  // method's start and coefficients take them there).
  template <class X>
  static double K(const X& x, const Params<double>& c) {
    static_assert(std::same_as<X, StateView<double>>,
                  "a proxy scene evaluates K, not its partials");
    return step_kernel().K(x.q, x.p, x.z, x.t, c.v);
  }
  static bool diverged(const double* q, const double* p) { return step_kernel().diverged(q, p); }
  static void natural_frequencies(const Params<double>& c, double* omega) {
    step_kernel().natural_frequencies(c.v, omega);
  }
  // The scene's own answers (lane_health.hpp's defined_at, lane_state.hpp's log_lambda).
  static bool defined_at(const LaneState<D>& x, const Params<double>& c) {
    return step_kernel().defined_at(&x, c.v);
  }
  static double log_lambda(const LaneState<D>& x) { return step_kernel().log_lambda(&x); }

  // The energy trap (engine/mappers/energy_trap.hpp) is compiled for every proxy, and serves
  // where the kernel was built with it (a basin map that uses it); its uses of K are the
  // kernel's (energy_wells.hpp's trap_ functions). The table's address names the K, for the
  // wells the trap keeps per process.
  static constexpr bool may_have_energy_trap = true;
  static bool run_time_energy_trap() { return step_kernel().trap.used; }
  static const void* identity() { return &step_kernel(); }
  template <class Tile>
  static void tile_energy(const Tile& t, const Params<double>* uniform, double* energy) {
    step_kernel().trap.tile_energy(&t.q[0][0], &t.p[0][0], &t.param_field[0][0],
                                   uniform != nullptr ? uniform->v : nullptr, energy);
  }
  static double trap_potential(const double* q, const Params<double>& c) {
    return step_kernel().trap.potential(q, c.v);
  }
  static BasinBox<D> confining_box(const Params<double>& c, const BasinBox<D>& positions,
                                   const std::array<double, D>& widen, double e0, double h) {
    BasinBox<D> box;
    step_kernel().trap.box(c.v, &positions, widen.data(), e0, h, &box);
    return box;
  }
  static Wells<D> find_wells(const Params<double>& c, const BasinBox<D>& box, double h) {
    Wells<D> wells;
    step_kernel().trap.wells(c.v, &box, h, &wells);
    return wells;
  }
  static bool well_bottom(const Params<double>& c, const BasinBox<D>& box, double h,
                          const double* q, const Wells<D>& wells, std::array<double, D>& minimum) {
    return step_kernel().trap.well_bottom(c.v, &box, h, q, &wells, minimum.data());
  }
};

template <class S>
concept ProxiedScene = Scene<S> && requires { requires S::is_proxy; };

struct ProxyMethod {
  template <class T>
  struct Coef {
    T v[kStepKernelCoefFields];
    static int used_fields() { return step_kernel().coef_fields; }  // LaneTile moves these
  };
  template <Scene S>
  static Coef<double> coefficients(double h, const ParamsOf<S, double>& c,
                                   const LaneState<S::dof>& x) {
    Coef<double> k{};
    step_kernel().coefficients(h, c.v, &x, k.v);
    return k;
  }
  template <Scene S>
  static bool breaks_down(const Coef<double>& k) {
    return step_kernel().breaks_down(k.v);
  }
  template <Scene S, class C>
  static void start(LaneState<S::dof>& x, const C& c) {
    step_kernel().start(&x, c.v);
  }
  // One lane's step, for the stop's rerun (engine/block_runner_stop.hpp); the carried state is
  // the kernel's.
  template <Scene S, Carry, class C, class K>
  static void step(LaneState<S::dof>& x, const C& c, const K& k) {
    step_kernel().step(&x, c.v, k.v);
  }
};

// The run's measures as formulas where the kernel holds them (StepKernelFormulas): the runner's
// formula tracker (engine/measures/observables.hpp) with room for kStepKernelMaxObservables and
// a stop, the kernel's own count and stop at run time (read through engine/run_traits.hpp); λ
// where the formulas read it. Their work after every step runs in the kernel's step loop
// (FormulaTracker::advance_in_kernel).
struct ProxyFormulas {
  static constexpr bool is_proxy = true;
  static constexpr int observables = kStepKernelMaxObservables;
  static constexpr bool stop = true;
  static constexpr bool reads_lambda = true;
  static int run_time_observables() { return step_kernel().formulas.observables; }
  static bool run_time_stop() { return step_kernel().formulas.stop; }
  static bool run_time_reads_lambda() { return step_kernel().formulas.reads_lambda; }
  template <int D, class C>
  static void observe(const ObservableView<D>& x, const C& c, double* v) {
    step_kernel().formulas.observe(x.q, x.p, x.z, x.t, x.lambda, c.v, v);
  }
  template <int D, class C>
  static bool stops(const ObservableView<D>& x, const C& c) {
    return step_kernel().formulas.stops(x.q, x.p, x.z, x.t, x.lambda, c.v);
  }
  template <int D, class C>
  static double exit(const ObservableView<D>& x, const C& c) {
    return step_kernel().formulas.exit(x.q, x.p, x.z, x.t, x.lambda, c.v);
  }
  static void advance_watched(void* tile, int steps, const double* uniform_params,
                              const double* uniform_coef, double t_start, double h, int which,
                              void* steps_state) {
    step_kernel().advance_watched(tile, steps, uniform_params, uniform_coef, t_start, h, which,
                                  steps_state);
  }
};

// The step loop: the kernel's, chosen over lane_tile.hpp's as the more constrained template.
template <ProxiedScene S, class Method, Carry carry, bool Uniform, int W, int PF, int CF,
          class AfterStep>
inline void advance(LaneTile<S, Method, W, PF, CF>& t, int steps,
                    const ParamsOf<S, double>& uniform,
                    const typename Method::template Coef<double>& uniform_coef, double t_start,
                    double h, AfterStep&&) {
  step_kernel().advance(&t, steps, uniform.v, uniform_coef.v, t_start, h);
}

}  // namespace cs
