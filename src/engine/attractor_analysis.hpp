// Each attractor of a basin map described (INTERFACE.md, "Attractors of every kind";
// docs/basins.md, "What each attractor is"): its kind, its largest Lyapunov exponent, its period
// in time units and samples along it, from one lane integrated from the table's point.
//
// The table is the same bits on every rank, and so is this pass: it reads the table and the spec
// alone (rank 0 computes it; sweep.cpp). The orbit itself needs the scene's and method's
// templates on dual numbers, so it runs in a kernel built at run time (attractor_orbit.hpp, the
// orbit kernel of kernel_build/kernel_source.hpp); this file asks for it and classifies what
// comes back.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/fixed_point_exponent.hpp"

namespace cs {

struct RunPlan;
struct Attractor;

// `exit`: a stop's exit channel (measures.stop with basin: attractor_period −1), an outcome
// of the map that is no attractor; its λ₁, period and samples are NaN.
enum class AttractorKind : int { fixed_point = 0, periodic = 1, quasiperiodic = 2, chaotic = 3, exit = 4 };
inline constexpr const char* kAttractorKindMeanings = "fixed_point periodic quasiperiodic chaotic exit";

// Samples along each attractor (the file's `point` dimension).
inline constexpr int kAttractorSamples = 256;
// A tangent that grows by less than e^10 (≈ 2·10⁴) over the measuring window is not taken for
// chaos: on a limit cycle or a torus the tangent stays bounded, but not constant (along a cycle
// it follows the speed, transverse to it the contraction or a shear), and its finite-time
// exponent is that bounded log-ratio over the window. Chaotic: λ₁ > kChaosEfolds / window.
inline constexpr double kChaosEfolds = 10.0;

// One lane's orbit, as the kernel is asked to integrate it (orbit_request: from the plan alone).
struct OrbitRequest {
  std::vector<double> params;  // the scene's, catalog order
  std::vector<double> state;   // q.., p.., z, lambda: the attractor's point, the grid point's z
  std::vector<double> seed;    // the tangent's start, q.., p.., z (tangent_lyapunov.hpp)
  double log_norm0 = 0.0;      // ln ‖seed‖
  // Start the tangent in q alone when the q motion is a system of its own (q' = K_p reads
  // neither p nor z: a cotangent lift K = p·F(q)); found by the kernel on the first steps.
  bool seed_q_where_closed = false;
  double h = 0.0, t_start = 0.0;
  std::int64_t transient_steps = 0, window_steps = 0;
  std::int64_t sample_steps = 0;  // between samples: one forcing period when stroboscopic
  int samples = kAttractorSamples;
  bool stroboscopic = false;
  double tolerance = 0.0;            // the basin's
  std::vector<double> angle_period;  // q.., p..: 0 where not an angle
};

// What the kernel found along it.
struct AttractorOrbit {
  std::vector<double> points;   // samples × (q.., p..)
  double lyapunov = 0.0;        // over the window
  double return_time = 0.0;     // autonomous: first return, NaN if none
  int stroboscopic_return = 0;  // first k > 0 with sample k within tolerance of sample 0
  bool moved = false;           // some sample further than the tolerance from the first
  bool finite = true;           // false: broke down or diverged
};

using OrbitFn = void (*)(const OrbitRequest&, AttractorOrbit&);

// A table fixed point whose exact λ₁ exceeds this many times ‖J‖∞ is unstable beyond doubt,
// and no attractor (unstable_fixed_point). Why this margin: the eigenvalues Eigen computes are
// exact for J + E with ‖E‖ of a few m·u·‖J‖ (Hessenberg QR is backward stable; J's entries are
// rounded too), u = 2⁻⁵³ and m ≤ 7 the block's size. A true eigenvalue with real part ≤ 0 then
// reads at most about κ·‖E‖ above it when simple (κ its condition number) and
// (‖E‖/‖J‖)^(1/k)·‖J‖ when in a Jordan block of size k: a centre of a conservative K (±iω)
// reads ~10⁻¹⁶‖J‖, a double zero (a Bogdanov–Takens point) ~10⁻⁷‖J‖, a triple zero
// ~2·10⁻⁵‖J‖, all below 10⁻⁴‖J‖, as is a simple eigenvalue with κ up to 10¹⁰. A saddle
// refused has λ₁ ~ ‖J‖ (the Lorenz origin: 11.83 against ‖J‖∞ = 29); one whose λ₁ is under
// 10⁻⁴‖J‖ is kept, as before, the safe side: one e-fold away from it takes its lanes more
// than 10⁴/‖J‖ time units.
inline constexpr double kUnstableMargin = 1e-4;

struct AttractorAnalysis {
  AttractorKind kind = AttractorKind::fixed_point;
  double lyapunov = 0.0;       // 1/time; NaN where not computed
  double time_period = 0.0;    // time units; NaN unless periodic
  std::vector<double> points;  // kAttractorSamples × (q.., p..)
};

// The Jacobian at the table's fixed point `a`, from one evaluation of `fixed`: `a`'s own where
// the table holds it (merge_candidates evaluates each once, on every rank alike), else now.
// The default (NaN, defined) where neither its λ₁ nor whether a lane from it breaks down is
// asked: no `fixed`, not a fixed point of an autonomous scene, or z feeds back or K reads t and
// no source lane.
FixedPointLinearisation linearisation_of(const RunPlan& plan, const Attractor& a,
                                         FixedPointExponentFn fixed);

// Is the table's fixed point `a` (its linearisation `j`) unstable, hence no attractor? Where
// its exact λ₁ applies (a fixed point of an autonomous scene, z not feeding back, K not reading
// t, J defined and the field vanishing at the point) and exceeds kUnstableMargin·‖J‖∞. False
// wherever the exact λ₁ is not available: those are kept, as before.
bool unstable_fixed_point(const RunPlan& plan, const Attractor& a,
                          const FixedPointLinearisation& j);

// Does describing `table` need the kernel's orbits? Not where every attractor is a fixed point
// of an autonomous scene (the energy trap's and the anchor test's) whose z does not feed back
// and where `fixed` gives its λ₁: those are described from the table alone, so such maps build
// no kernel. (Where z feeds back or K reads t, the table's point and the run's t_start do not
// fix the linearisation; where `fixed` gives NaN, its Jacobian is undefined at the point or the
// point is no fixed point: the orbit describes it. Without `fixed`, every attractor.)
bool needs_orbits(const RunPlan& plan, const std::vector<Attractor>& table,
                  FixedPointExponentFn fixed);
// Can the map's table hold an attractor that needs one, before it is made? Where the
// recurrences or the stroboscopic map look for attractors, or where z feeds back or K reads t.
// Not where the energy trap and the anchor test find fixed points alone: a table whose point
// falls back to its orbit all the same (needs_orbits) has its orbit kernel built after the map.
bool may_need_orbits(const RunPlan& plan);

// `from_source_lane`: start where the attractor's source lane started, the whole run as the
// transient, as an attractor found by recurrences does (a fixed point whose formulas are
// undefined at its point: analyse_attractors).
OrbitRequest orbit_request(const RunPlan& plan, const Attractor& a, bool from_source_lane = false);

// From the orbit (`orbit` == nullptr: a fixed point described from the table alone). A fixed
// point of the table takes its λ₁ from `j` (linearisation_of(plan, a, fixed)), exact, where z
// does not feed back, K does not read t and the Jacobian applies at the point (not NaN); else
// from the orbit.
AttractorAnalysis classify(const RunPlan& plan, const Attractor& a, const OrbitRequest& request,
                           const AttractorOrbit* orbit, const FixedPointLinearisation& j = {});

// Every attractor of the table; `orbit` may be null when !needs_orbits(plan, table, fixed).
std::vector<AttractorAnalysis> analyse_attractors(const RunPlan& plan,
                                                  const std::vector<Attractor>& table,
                                                  OrbitFn orbit,
                                                  FixedPointExponentFn fixed = nullptr);

}  // namespace cs
