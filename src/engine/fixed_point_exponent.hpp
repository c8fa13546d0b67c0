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

#include <vector>

namespace cs {

struct RunPlan;

// `params` in the plan's scene's order, `state` q.., p.., z at the fixed point; NaN where J is
// not finite. Safe from any thread (the formula's symbolic work is serialised).
double fixed_point_exponent(const RunPlan& plan, const std::vector<double>& params,
                            const std::vector<double>& state);

}  // namespace cs
