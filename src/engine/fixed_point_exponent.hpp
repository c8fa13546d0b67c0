// λ₁ at a fixed point of a built-in scene's basin map, where no kernel is built (the energy
// trap's and the anchor test's maps: attractor_analysis.hpp). At a fixed point x* of the flow
// the tangent obeys δx' = J δx with J the Jacobian of the contact vector field (q' = K_p,
// p' = −K_q + p K_z, and z' = K − p·K_p where z feeds back), so the largest Lyapunov exponent is
// the largest real part of J's eigenvalues: exact, with no finite-time error (the damped
// oscillator's −γ/2). It is the flow's exponent, not the integrator's map's, which differs by
// O(h^order) — the finite-time estimate a K scene's kernel gives tends to the latter.
#pragma once

#include <vector>

namespace cs {

struct RunPlan;

// `params` in catalog order, `state` q.., p.., z at the fixed point; NaN where J is not finite.
// Only for built-in scenes (the name in plan.scene): std::logic_error otherwise.
double fixed_point_exponent(const RunPlan& plan, const std::vector<double>& params,
                            const std::vector<double>& state);

}  // namespace cs
