// Contact splitting integrators of Bravetti, Seri, Vermeeren, Zadra (2020): compositions of the
// exact flows of K = Σ p²/2 + V(q) + Z(z) (numerics/split_flows.hpp).
//
// The base step is the symmetric (Strang) composition, second order and time-symmetric:
//
//   S₂(τ) = φ_Z(τ/2) ∘ φ_V(τ/2) ∘ φ_{p²/2}(τ) ∘ φ_V(τ/2) ∘ φ_Z(τ/2)
//
// Z outermost: then V′ is needed only between flows that leave q alone (below). The order of the
// parts inside S₂ is a choice; with Z in the middle instead, the 4th-order composition's stability
// limit on scene A (ω = 1, γ = 0.1) would be h < 1.5651 rather than this one's 1.5706.
//
// A higher-order method is S₂ composed over a table of weights w_s (Σ w_s = 1, palindromic):
// S(h) = S₂(w_m h) ∘ … ∘ S₂(w_1 h). A new composition is a new table, never new code: a file in
// numerics/methods/ holding the table and its description (contact_splitting4.hpp).
//
// V′ is needed at the start and end of each S₂: a kick and the Z flow leave q alone, so the
// force at the end of one S₂ is the force at the start of the next, and of the next step's first
// S₂ (kept in LaneState::kq): one force evaluation per S₂. With z carried, V comes from the same
// evaluation (the value part of the dual), plus one V per step at the start.
//
// Each sub-flow is exact, so each S₂ is a contact map and the composition conserves the
// modified H of a nearby contact Hamiltonian: |ΔH/H| stays bounded (tests/test_methods.cpp).
//
// Time-dependent K (V(q, t), k(t)): t is a coordinate moved by the kinetic flow, so S₂ number s
// takes its first V and Z flows at t_n + offset[s] and its last ones at t_n + offset[s + 1]
// (Bravetti et al. 2020): each S₂ stays symmetric and the compositions keep orders 4 and 6.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string_view>

#include "numerics/lane_math.hpp"
#include "numerics/method_description.hpp"
#include "numerics/split_flows.hpp"

namespace cs {

// The sub-flows every splitting method composes. The step solves both shapes of Z a scene can
// offer (z_linear, z_quadratic); the list cannot say "one of", so it names the parts every such
// scene must offer (MethodDescription::needs_split_parts).
inline constexpr std::string_view kSplitFlowParts[] = {"kinetic", "potential"};

// ---- the generic composition -------------------------------------------------------------------

// Composition: the weights (a palindromic std::array summing to 1) and the method's
// MethodDescription (numerics/methods/contact_splitting*.hpp).
template <class Composition>
struct ContactSplitting {
  static constexpr MethodDescription description = Composition::description;
  static constexpr int stages = static_cast<int>(Composition::weights.size());
  static constexpr int order = description.order;
  static_assert(description.force_evaluations_per_step == stages, "one force evaluation per S₂");

  template <class T>
  struct Coef {
    T tau[stages];    // w_s·h, the length of each S₂
    T half[stages];   // w_s·h/2
    T decay[stages];  // e^{k·w_s·h/2}, the linear Z flow over half an S₂
    T k;              // Z = k·z or k·z²
    T dmu;            // −k·h: the exact change of ln λ over a whole step when Z is linear
    T offset[stages + 1];  // time-dependent K: S₂ number s runs from t_n + offset[s] to
                           // t_n + offset[s + 1] (offset[stages] = h exactly)
  };

  template <Scene S>
  static Coef<double> coefficients(double h, const ParamsOf<S, double>& c,
                                   const LaneState<S::dof>&) {
    Coef<double> coef{};
    if constexpr (!SplittableScene<S>) {
      // The spec parser refuses such a pair (MethodInfo::needs_split_parts): never reached.
      throw std::logic_error("contact splitting needs a scene with split parts");
    } else {
      coef.k = z_coefficient<S>(c, 0.0);  // used only where it does not depend on t
      coef.dmu = -coef.k * h;
      double elapsed = 0.0;
      for (int s = 0; s < stages; ++s) {
        coef.tau[s] = Composition::weights[s] * h;
        coef.half[s] = 0.5 * coef.tau[s];
        coef.decay[s] = std::exp(coef.k * coef.half[s]);
        coef.offset[s] = elapsed * h;
        elapsed += Composition::weights[s];
      }
      coef.offset[stages] = h;
    }
    return coef;
  }

  // Exact flows never break down for a linear Z; a quadratic Z reports it per step.
  template <Scene S>
  static bool breaks_down(const Coef<double>&) {
    return false;
  }

  // The first kick needs V′ at the initial state.
  template <Scene S, class T, class C>
  static void start(LaneState<S::dof, T>& x, const C& c) {
    if constexpr (SplittableScene<S>)
      for_each_dof<S::dof>([&](auto i) { x.kq[i] = potential_force<S, i>(x.q, c, x.t); });
  }

  // Forced inline, with everything it calls: the kernel's lane loop vectorises only if the whole
  // step is one straight block inside it (a step of this size exceeds GCC's inlining limits).
  // P, the coefficients' number type, is T or double: the tangent step (T = Dual<double>) takes
  // them as plain doubles (plain_coefficients), which spares the products with their zero
  // derivative parts; the value parts are the same operations either way.
  static constexpr bool plain_coefficients = true;

  template <Scene S, Carry carry, class T, class C, class P>
  [[gnu::always_inline, gnu::flatten]] static void step(LaneState<S::dof, T>& x,
                                                        const C& c, const Coef<P>& k) {
    if constexpr (SplittableScene<S>) {
      constexpr bool with_z = carry.z || S::z_feeds_back;
      const T t0 = x.t;
      T v{};  // V at the current q, needed only for z
      if constexpr (with_z) v = potential<S>(x.q, c, t0);
      // for_each_dof is the generic compile-time loop: unrolled, so s indexes the table as a
      // constant and the step stays one straight block.
      for_each_dof<stages>([&](auto s) {
        const T ta = t0 + k.offset[s], tb = t0 + k.offset[s + 1];
        z_flow<S, carry>(x, k, s, c, ta);
        potential_flow<with_z>(x, k.half[s], x.kq, v);
        kinetic_flow<with_z>(x, k.tau[s]);
        refresh_force<S, with_z>(x, c, v, tb);
        potential_flow<with_z>(x, k.half[s], x.kq, v);
        z_flow<S, carry>(x, k, s, c, tb);
      });
      if constexpr (S::z_part == ZPart::linear && carry.mu && !z_varies<S>())
        x.mu = x.mu + k.dmu;
    }
  }

 private:
  // Does k in Z = k·z (k·z²) change with time? Then it is taken at each flow's time.
  template <SplittableScene S>
  static constexpr bool z_varies() {
    return time_dependent<S>() && !S::kz_constant;
  }

  // Z over half an S₂, at time t (which matters only where k depends on it).
  template <SplittableScene S, Carry carry, class T, class C, class P>
  static void z_flow(LaneState<S::dof, T>& x, const Coef<P>& k, int s, const C& c,
                     T t) {
    constexpr bool with_z = carry.z || S::z_feeds_back;
    if constexpr (!z_varies<S>()) {
      if constexpr (S::z_part == ZPart::linear)
        linear_z_flow<with_z>(x, k.decay[s]);
      else
        quadratic_z_flow<carry.mu>(x, k.k, k.half[s]);
    } else {
      const T kt = z_coefficient<S>(c, t);
      if constexpr (S::z_part == ZPart::linear) {
        linear_z_flow<with_z>(x, lane_math::exp(kt * k.half[s]));
        if constexpr (carry.mu) x.mu = x.mu - kt * k.half[s];
      } else {
        quadratic_z_flow<carry.mu>(x, kt, k.half[s]);
      }
    }
  }

  template <SplittableScene S, bool with_z, class T, class C>
  static void refresh_force(LaneState<S::dof, T>& x, const C& c, T& v, T t) {
    for_each_dof<S::dof>([&](auto i) {
      if constexpr (with_z)
        potential_and_force<S, i>(x.q, c, t, v, x.kq[i]);
      else
        x.kq[i] = potential_force<S, i>(x.q, c, t);
    });
  }
};

}  // namespace cs
