// λ₁ at a fixed point of a basin map's table (the energy trap's and the anchor test's maps:
// attractor_analysis.hpp), for a built-in scene and a scene.K alike, with no kernel and no orbit.
// At a fixed point x* of the flow the tangent obeys δx' = J δx with J the Jacobian of the
// contact vector field (q' = K_p, p' = −K_q + p K_z, and z' = K − p·K_p where z feeds back), so
// the largest Lyapunov exponent is the largest real part of J's eigenvalues: exact, with no
// finite-time error (the damped oscillator's −γ/2). J comes from K's exact partials
// (formula/contact_jacobian.hpp), so a built-in scene and the same K written in the spec get the
// same bits. It is the flow's exponent, not the integrator's map's, which differs by O(h^order).
// Where q' = K_p reads neither p nor z (a cotangent lift K = p·F(q)) it is the q system's, from
// J's q block: p carries the adjoint, whose exponents are the q system's negated (the orbit's
// tangent is seeded in q alone there for the same reason).
#pragma once

#include <limits>
#include <vector>

namespace cs {

struct RunPlan;

// What the Jacobian says at a point, from one evaluation: `lyapunov` as fixed_point_exponent
// returns it (NaN where it does not apply there); `undefined` where J itself is not defined
// there, whatever the tolerance (an entry not finite, or no eigenvalues): a lane started at the
// point would break down; `norm` ‖J‖∞ over the block whose eigenvalues give λ₁ (NaN where
// undefined), the scale against which rounding can move them (attractor_analysis.hpp,
// unstable_fixed_point).
struct FixedPointLinearisation {
  double lyapunov = std::numeric_limits<double>::quiet_NaN();
  bool undefined = false;
  double norm = std::numeric_limits<double>::quiet_NaN();
};

// `params` in the plan's scene's order, `state` q.., p.., z at the fixed point. NaN where the
// Jacobian does not apply: an entry of J is not finite there (GiNaC's partials can be 0/0 at a
// point where K is smooth: sqrt(q^4)), or, with a finite `tolerance` (a basin map's table:
// its attractors' tolerance), (q', p') does not vanish there to within 2·τ·‖J‖∞ (max norms over
// q and p; the rule and why: fixed_point_exponent.cpp), so the state is no fixed point: the
// caller describes it by its orbit instead (attractor_analysis.hpp). With the default
// tolerance the caller vouches for the state. Safe from any thread (the formula's symbolic work
// is serialised).
double fixed_point_exponent(const RunPlan& plan, const std::vector<double>& params,
                            const std::vector<double>& state,
                            double tolerance = std::numeric_limits<double>::infinity());
// The same evaluation, with whether the Jacobian is undefined at the point and its norm: a
// basin map's table asks all three once per attractor (attractor_analysis.hpp).
FixedPointLinearisation fixed_point_linearisation(const RunPlan& plan,
                                                  const std::vector<double>& params,
                                                  const std::vector<double>& state,
                                                  double tolerance);

// The same, as a basin map's table and its description take it (attractor_table.hpp,
// attractor_analysis.hpp): tests may stand in for it.
using FixedPointExponentFn = FixedPointLinearisation (*)(const RunPlan&,
                                                         const std::vector<double>& params,
                                                         const std::vector<double>& state,
                                                         double tolerance);

}  // namespace cs
