// What the block runner and the formula tracker ask of a run's scene and of its measures as
// formulas, answered in one place. A scene and formulas compiled into the kernel (a built-in
// scene, a whole kernel's generated struct) answer at compile time, and the runner's passes are
// specialised on them. A step kernel's proxy scene and proxy formulas (engine/proxy_scene.hpp)
// answer at run time from the kernel's table: their compile-time members are then the runner's
// room (what it is compiled to handle), not the run's own.
#pragma once

#include "numerics/lane_state.hpp"
#include "physics/scene_concept.hpp"

namespace cs {

// The scene's traits that decide what a lane's step writes and what the runner checks after it.
template <Scene S, Carry carry>
struct SceneTraits {
  static constexpr bool at_run_time = requires { S::run_time_traits(); };
  // K_z constant: a lane's breakdown flag is never set.
  static bool kz_constant() {
    if constexpr (at_run_time) return S::run_time_traits().kz_constant;
    else return S::kz_constant;
  }
  // K reads t: a lane's time (its step count) is read by the step.
  static bool time_dependent() {
    if constexpr (at_run_time) return S::run_time_traits().time_dependent;
    else return cs::time_dependent<S>();
  }
  // The fields a lane's step writes besides q, p and the breakdown flag.
  static bool carries_z() {
    if constexpr (at_run_time) return S::run_time_traits().carries_z;
    else return carry.z || S::z_feeds_back;
  }
  static bool carries_mu() {
    if constexpr (at_run_time) return S::run_time_traits().carries_mu;
    else return carry.mu;
  }
};

// The run's measures as formulas (engine/measures/observables.hpp). M::observables and M::stop
// say what the runner is compiled for; these, what the run has.
template <class M>
struct FormulaTraits {
  // A step kernel's formulas, whose work after every step runs in the kernel's step loop.
  static constexpr bool in_step_kernel = requires { requires M::is_proxy; };
  static int observables() {
    if constexpr (in_step_kernel) return M::run_time_observables();
    else return M::observables;
  }
  static bool stop() {
    if constexpr (!M::stop) return false;
    else if constexpr (in_step_kernel) return M::run_time_stop();
    else return true;
  }
  static bool reads_lambda() {
    if constexpr (!M::reads_lambda) return false;
    else if constexpr (in_step_kernel) return M::run_time_reads_lambda();
    else return true;
  }
};

}  // namespace cs
