#!/usr/bin/python3
"""Each attractor described (issue 23 item 2; docs/basins.md, "What each attractor is"):
attractor_kind, attractor_lyapunov, attractor_time_period, attractor_points.

    test_attractor_analysis.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

* Van der Pol at mu = 1 by cotangent lift (K = p1*q2 + p2*(mu*(1 - q1^2)*q2 - q1)): one
  attractor, periodic, time period 6.6632868593... within rk4's period error (h L)^4/120 * T
  (L the largest |Df| on the cycle) plus the parabolic interpolation of the return,
  h^3 max|g'''| / (9 sqrt 3 |g'|); amplitude max|q1| over the samples 2.0086198609... within
  |q1''| / 2 ((T/K + h) / 2)^2 (samples at the steps nearest k T / K); lambda_1 within
  (ln(max|F|/min|F|) + ln 2) / W (the tangent aligns with the flow F; W the window), and
  kind periodic needs it below the chaos threshold 10 / W.
* The linear forced oscillator written autonomously (q3 the forcing's phase, an angle, by
  cotangent lift): one periodic attractor, period 2 pi / Omega and amplitude
  F / sqrt((w^2 - Omega^2)^2 + c^2 Omega^2), with the same bounds.
* A torus that attracts (q1' = 1, q2' = golden mean, q3' = -q3, angles q1, q2): quasiperiodic,
  lambda_1 = ln(sqrt(2/3)) / W exactly (the tangent's q3 part decays).
* The damped double well written as K: two fixed points (kind 0, no period), the points at
  (+-1, 0), lambda_1 = -gamma/2 (the linearisation's eigenvalues -gamma/2 +- i sqrt(2 -
  gamma^2/4)) to rounding, from K's exact Jacobian as for the built-in scene: the same bits.
* The chaotic forced Duffing (delta = 0.3, F = 0.5, Omega = 1.2) on its stroboscopic map: one
  attractor, kind chaotic, lambda_1 against the DOP853 + variational reference (0.10514, sd
  0.0062 over T = 10^4, tests/reference/duffing_lyapunov.py) within 4 sd scaled to the window
  plus the tangent's alignment transient, 200 lambda / W.
* The built-in double well's map builds no kernel: kind 0, the points its wells, lambda_1 the
  linearised flow's -gamma/2 (exact: engine/fixed_point_exponent.hpp) to rounding.
* Fixed points where the Jacobian does not apply: K = p^2/2 + sqrt(q^4)/2 - gamma z (its
  partials 0/0 at the trap's minimum) and the kink of V = q^2/2 + 0.1|q| (rk4 chatters; the
  anchor test's points are no fixed points, |p'| ~ 0.1): their lanes describe them, built after
  the map, lambda_1 = -gamma/2 within ln cond(P) / W (the eigenvectors' condition number bounds
  the tangent's bounded factor), not the Jacobian's exact bits.
* The orbit is a kernel of its own (kernel_build/kernel_source.hpp), built only where a map can
  find an attractor that is not a fixed point: a K run without a basin map builds its step
  kernel alone, and so does the double well's map as K (the energy trap's fixed points); the
  next map of the same K builds nothing; a K whose map looks by recurrences (van der Pol)
  builds the orbit kernel, which holds nothing else, beside its runner's (a second compiler at
  the same time, before the map); a built-in
  scene on its stroboscopic map builds the orbit kernel alone; the built-in double well with
  lyapunov (a kernel, no orbit needed) describes its attractors as it does without it, bit for
  bit.
* The new datasets are the same bits for 1 x 1, 1 x 2 and 2 x 1 ranks x threads (whole files).
"""
import math
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs, launch  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True)  # makes work/, the kernel cache in it
check = runs.check


def run(spec_text, name, ranks=0, threads=1, env_extra=None):
    out, result = launch(binary, mpiexec, work, spec_text, name, ranks=ranks, threads=threads,
                         env_extra=env_extra, quiet=False)
    if result.returncode != 0:
        check(f"{name} runs", False, result.stderr.strip()[-2000:])
        return None, ""
    return out, result.stdout + result.stderr


def table(path):
    with h5py.File(path, "r") as f:
        kind = f["attractor_kind"]
        check(f"{os.path.basename(path)}: attractor_kind's flags",
              # the contract's four kinds, and 4 for a stop's exits (not an attractor)
              list(kind.attrs["flag_values"]) == [0, 1, 2, 3, 4]
              and kind.attrs["flag_meanings"] == "fixed_point periodic quasiperiodic chaotic exit"
              and kind.dtype == np.int8 and f["attractor_points"].dims[1][0].name == "/point",
              f"{kind.attrs.get('flag_values')} {kind.attrs.get('flag_meanings')} {kind.dtype}")
        return {k: f[k][...] for k in ("attractor_kind", "attractor_lyapunov",
                                       "attractor_time_period", "attractor_points",
                                       "attractor_period")}


def same_bits(reference, spec_text, name):
    for ranks, threads in ((0, 2), (2, 1)):
        other, _ = run(spec_text, f"{name}_{max(ranks, 1)}x{threads}", ranks=ranks, threads=threads)
        if other:
            same = subprocess.run([sys.executable, compare, reference, other], capture_output=True,
                                  text=True)
            check(f"{name} {max(ranks, 1)}x{threads} has the bits of 1x1", same.returncode == 0,
                  same.stdout + same.stderr)


def cycle_checks(name, t, points, F, jac, period, amplitude, h, window):
    """A limit cycle's period, amplitude and lambda_1 against closed values, tolerances derived."""
    T, lam = t["attractor_time_period"][0], t["attractor_lyapunov"][0]
    K = points.shape[0]
    check(f"{name}: one attractor, periodic", t["attractor_kind"].tolist() == [1],
          f"{t['attractor_kind']}")
    speed = np.linalg.norm(F(points), axis=1)
    L = max(np.linalg.norm(jac(x), 2) for x in points)
    f0 = F(points[:1])[0]
    # g(t) = (x(t) - x0).v0 with v0 = h F(x0): g' = h F.F(x0) at the return and g''' = h
    # x'''.F(x0), x''' = d/dt (Df F) by a difference along the flow.
    def second(x):
        return np.stack([jac(a) @ b for a, b in zip(x, F(x))])
    e = 1e-5
    third = (second(points + e * F(points)) - second(points)) / e
    interpolation = h ** 3 * np.max(np.abs(third @ f0)) / (9 * math.sqrt(3) * (f0 @ f0))
    tol_T = (h * L) ** 4 / 120 * period + interpolation
    check(f"{name}: time period {period:.10f}", abs(T - period) <= tol_T,
          f"{T:.10f}, error {abs(T - period):.2e}, tolerance {tol_T:.2e}")
    q1 = points[:, 0]
    curvature = np.max(np.abs(F(points)[:, 1]))  # |q1''| = |q2'| bounds it (q1' = q2)
    tol_A = curvature / 2 * ((period / K + h) / 2) ** 2
    check(f"{name}: amplitude {amplitude:.10f}", abs(np.max(np.abs(q1)) - amplitude) <= tol_A,
          f"{np.max(np.abs(q1)):.8f}, error {abs(np.max(np.abs(q1)) - amplitude):.2e}, "
          f"tolerance {tol_A:.2e}")
    bound = (np.log(speed.max() / speed.min()) + np.log(2.0)) / window
    check(f"{name}: |lambda_1| <= ln(max|F|/min|F|)/W + ln 2/W", abs(lam) <= bound,
          f"{lam:.3e} vs {bound:.3e}")


# ---- van der Pol ------------------------------------------------------------------------------
VDP = """[scene]
K = "p1*q2 + p2*(mu*(1 - q1^2)*q2 - q1)"
label = "van_der_pol"
mu = 1.0
[integrator]
method = "rk4"
h = 0.01
t_end = 500.0
[grid]
q1_0 = { from = -3.0, to = 3.0, n = 32 }
q2_0 = { from = -3.0, to = 3.0, n = 32 }
[measures]
basin = { locate = 300 }
"""
vdp, _ = run(VDP, "vdp_1x1")
if vdp:
    t = table(vdp)
    pts = t["attractor_points"][0]
    check("van der Pol: the samples stay on p = 0", np.all(pts[:, 2:] == 0.0), f"{pts[:3]}")
    q = pts[:, :2]

    def f_vdp(x):
        return np.stack([x[:, 1], (1 - x[:, 0] ** 2) * x[:, 1] - x[:, 0]], axis=1)

    def j_vdp(x):
        return np.array([[0.0, 1.0], [-2 * x[0] * x[1] - 1, 1 - x[0] ** 2]])

    cycle_checks("van der Pol", t, q, f_vdp, j_vdp, 6.6632868593231301, 2.0086198608,
                 0.01, 500.0)
    same_bits(vdp, VDP, "vdp")

# ---- the linear forced oscillator, written autonomously ----------------------------------------
# q1'' + c q1' + w^2 q1 = F cos(q3), q3' = Omega: an angle (period 2 pi), by cotangent lift.
W_, C_, F_, OMEGA_ = 1.0, 0.4, 0.5, 1.5
FORCED = f"""[scene]
K = "p1*q2 + p2*(-w^2*q1 - c*q2 + F*cos(q3)) + p3*Omega"
label = "forced_linear_autonomous"
w = {W_!r}
c = {C_!r}
F = {F_!r}
Omega = {OMEGA_!r}
[integrator]
method = "rk4"
h = 0.01
t_end = 200.0
[grid]
q1_0 = {{ from = -1.0, to = 1.0, n = 16 }}
q2_0 = {{ from = -1.0, to = 1.0, n = 16 }}
[measures]
basin = {{ locate = 300, cell_size = 0.25, angles = {{ q3 = 6.283185307179586 }} }}
"""
forced, _ = run(FORCED, "forced_1x1")
if forced:
    t = table(forced)
    pts = t["attractor_points"][0][:, :3]

    def f_forced(x):
        return np.stack([x[:, 1], -W_ ** 2 * x[:, 0] - C_ * x[:, 1] + F_ * np.cos(x[:, 2]),
                         np.full(len(x), OMEGA_)], axis=1)

    def j_forced(x):
        return np.array([[0.0, 1.0, 0.0], [-W_ ** 2, -C_, -F_ * np.sin(x[2])], [0.0, 0.0, 0.0]])

    amplitude = F_ / math.sqrt((W_ ** 2 - OMEGA_ ** 2) ** 2 + (C_ * OMEGA_) ** 2)
    cycle_checks("forced oscillator (autonomous)", t, pts, f_forced, j_forced,
                 2 * math.pi / OMEGA_, amplitude, 0.01, 200.0)

# ---- a quasi-periodic attractor: an irrational winding on a torus that attracts ---------------
# q1' = 1, q2' = w (golden mean; both angles of period 2 pi), q3' = -q3: every orbit tends to the
# torus q3 = 0 and winds on it without closing (within 4 tolerances, the closest return of the
# golden winding needs ~150 windings, t ~ 1000 > the window). The tangent starts as (1, 1, 1) in q:
# its q1, q2 parts stay, its q3 part decays as e^-t, so lambda_1 = ln(sqrt 2 / sqrt 3) / W to
# within e^-W (rk4's own factor per step only changes how fast it decays).
TORUS = """[scene]
K = "p1 + p2*w + p3*(-q3)"
label = "torus"
w = 1.618033988749895
[integrator]
method = "rk4"
h = 0.01
t_end = 400.0
[grid]
q1_0 = { from = 0.0, to = 3.0, n = 4 }
q3_0 = { from = -1.0, to = 1.0, n = 4 }
[measures]
basin = { locate = 300, cell_size = 0.5, angles = { q1 = 6.283185307179586, q2 = 6.283185307179586 } }
"""
torus, _ = run(TORUS, "torus")
if torus:
    t = table(torus)
    expected = math.log(math.sqrt(2.0 / 3.0)) / 400.0
    check("torus: one attractor, quasiperiodic, no period",
          t["attractor_kind"].tolist() == [2] and np.isnan(t["attractor_time_period"][0]),
          f"{t['attractor_kind']} {t['attractor_time_period']}")
    check("torus: lambda_1 = ln(sqrt(2/3)) / W", abs(t["attractor_lyapunov"][0] - expected) <= 1e-12,
          f"{t['attractor_lyapunov'][0]!r} vs {expected!r}")
    check("torus: the samples lie on q3 = 0, p = 0",
          np.all(np.abs(t["attractor_points"][0][:, 2]) <= 1e-12)
          and np.all(t["attractor_points"][0][:, 3:] == 0.0), "")

# ---- fixed points: the damped double well written as K -------------------------------------------
GAMMA = 0.1
WELL = f"""[scene]
K = "p^2/2 + (q^2 - a*a)^2/2 - gamma*z"
label = "double_well_as_k"
a = 1.0
gamma = {GAMMA!r}
[integrator]
method = "rk4"
h = 0.01
t_end = 100.0
[grid]
q_0 = {{ from = -3.0, to = 3.0, n = 32 }}
p_0 = {{ from = -3.0, to = 3.0, n = 32 }}
[measures]
basin = {{}}
"""
well, _ = run(WELL, "well_k")
if well:
    t = table(well)
    check("double well as K: two fixed points, no period",
          t["attractor_kind"].tolist() == [0, 0] and np.all(np.isnan(t["attractor_time_period"])),
          f"{t['attractor_kind']} {t['attractor_time_period']}")
    pts = t["attractor_points"]
    check("double well as K: the samples are the minima (+-1, 0) to the trap's point",
          np.allclose(pts[:, :, 0], [[-1.0], [1.0]], atol=1e-9) and np.allclose(pts[:, :, 1], 0.0, atol=1e-9),
          f"{pts[:, 0]}")
    # At a minimum: A = [[0, 1], [-V'', -gamma]], V'' = 4 a^2, eigenvalues -gamma/2 +- i
    # sqrt(4 - gamma^2/4): A's entries are exact doubles, so lambda_1 is -gamma/2 to the eigen
    # solver's rounding (a few ulp of |A| ~ 4).
    check("double well as K: lambda_1 = -gamma/2 to rounding (K's exact Jacobian)",
          np.all(np.abs(t["attractor_lyapunov"] + GAMMA / 2) <= 1e-14),
          f"{t['attractor_lyapunov']!r} vs {-GAMMA / 2}")

# ---- the built-in double well: no kernel built, fixed points from the table -----------------------
BUILTIN = WELL.replace('K = "p^2/2 + (q^2 - a*a)^2/2 - gamma*z"\nlabel = "double_well_as_k"',
                       'name = "double_well"').replace('"rk4"', '"hybrid_leapfrog"')
fresh = os.path.join(work, "no_kernel_cache")
os.makedirs(fresh, exist_ok=True)
builtin, log = run(BUILTIN, "well_builtin", env_extra={"CONTACTSWEEP_CACHE": fresh})
if builtin:
    t = table(builtin)
    built = [n for n in os.listdir(fresh) if n.startswith("kernel-")]
    check("built-in double well: no kernel built", not built and "built the kernel" not in log,
          f"{built}")
    check("built-in double well: fixed points, lambda_1 = -gamma/2 exactly, period NaN, points the wells",
          t["attractor_kind"].tolist() == [0, 0]
          and np.all(np.abs(t["attractor_lyapunov"] + GAMMA / 2) <= 1e-14)
          and np.all(np.isnan(t["attractor_time_period"]))
          and np.allclose(t["attractor_points"][:, :, 0], [[-1.0], [1.0]]),
          f"{t['attractor_kind']} {t['attractor_lyapunov']} {t['attractor_points'][:, 0]}")
    if well:
        k = table(well)
        check("the double well as K describes its attractors as the built-in does, bit for bit",
              all(np.array_equal(t[n], k[n], equal_nan=True) for n in t),
              f"{t['attractor_lyapunov']!r} {k['attractor_lyapunov']!r}")

# ---- fixed points where the Jacobian does not apply: their lane describes them ------------------
# Both K are damped oscillators near the point, q'' + gamma q' + q = 0 to first order, so the
# tangent of rk4's step is M = R(hA), A = [[0, 1], [-1, -gamma]], wherever the lane is (the kink's
# 0.1|q| has no second derivative): with A = P diag(l, conj l) P^-1, |M^N v| / |v| lies within
# a factor cond(P) of |R(h l)|^N, so the window's lambda_1 is -gamma/2 to within ln cond(P) / W,
# plus rk4's |h l|^5 / (120 h) < 1e-9 per unit time. The Jacobian's value is -gamma/2 to the bit:
# a lane's value differs from it.
def ringing_bound(gamma, window):
    _, P = np.linalg.eig(np.array([[0.0, 1.0], [-1.0, -gamma]]))
    return math.log(np.linalg.cond(P)) / window + 1e-9


def fallback_spec(k, gamma, t_end, n):
    return f"""[scene]
K = "{k}"
gamma = {gamma!r}
[integrator]
method = "rk4"
h = 0.01
t_end = {t_end!r}
[grid]
q_0 = {{ from = -2.0, to = 2.0, n = {n} }}
p_0 = {{ from = -2.0, to = 2.0, n = {n} }}
[measures]
basin = {{}}
"""


# sqrt(q^4) = q^2, but GiNaC's K_q is 2 q^3 / sqrt(q^4), 0/0 at the trap's minimum q = 0 (the
# Jacobian there was NaN, and so was a lane started there): the lane starts where its source lane
# did. Its orbit kernel is built after the map (may_need_orbits cannot know before).
fallback_cache = tempfile.mkdtemp(prefix="orbit_fallback_cache.", dir=work)
quartic, log = run(fallback_spec("p^2/2 + sqrt(q^4)/2 - gamma*z", 0.25, 200.0, 8), "quartic",
                   env_extra={"CONTACTSWEEP_CACHE": fallback_cache})
if quartic:
    t = table(quartic)
    bound = ringing_bound(0.25, 200.0)
    lam = t["attractor_lyapunov"]
    check("sqrt(q^4): one fixed point at the origin, its orbit kernel built after the map",
          t["attractor_kind"].tolist() == [0] and "built the orbit kernel of scene.K to describe" in log
          and "beside it" not in log, f"{t['attractor_kind']}\n{log}")
    check("sqrt(q^4): lambda_1 = -gamma/2 within ln cond(P) / W (the lane's; the Jacobian is 0/0)",
          np.all(np.abs(lam + 0.125) <= bound) and np.all(lam != -0.125), f"{lam!r}, bound {bound:.2e}")

# V = q^2/2 + 0.1|q|: rk4's lanes chatter across the kink and the anchor test records points
# beside it where the field is no fixed point's, |p'| = |q + 0.1 sign q + gamma p| ~ 0.1 > 2 tau
# ||J||_inf = 2e-3 (1 + gamma). The lane describes them, not the Jacobian (-0.25 to the bit).
kink, log = run(fallback_spec("p^2/2 + q^2/2 + 0.1*abs(q) - gamma*z", 0.5, 100.0, 16), "kink",
                env_extra={"CONTACTSWEEP_CACHE": fallback_cache})
if kink:
    t = table(kink)
    with h5py.File(kink, "r") as f:
        q, p = f["attractor_q"][...], f["attractor_p"][...]
    speed = np.abs(q + 0.1 * np.sign(q) + 0.5 * p)
    check("kink: every table point has |p'| above the rule's 2 tau (1 + gamma)",
          len(q) > 0 and np.all(speed > 2e-3 * 1.5), f"q {q}, p {p}, |p'| {speed}")
    bound = ringing_bound(0.5, 100.0)
    lam = t["attractor_lyapunov"]
    check("kink: lambda_1 from the lanes, -gamma/2 within ln cond(P) / W, not the Jacobian's",
          np.all(t["attractor_kind"] == 0) and np.all(np.abs(lam + 0.25) <= bound)
          and np.all(lam != -0.25) and "built the orbit kernel of scene.K to describe" in log,
          f"{lam!r}, bound {bound:.2e}")

# ---- the orbit is a kernel of its own, built only for a table that needs it -----------------------
RUN_ENTRY, ORBIT_ENTRY = "contactsweep_run_block", "contactsweep_attractor_orbit"
STEP_ENTRY = "contactsweep_step_kernel"  # a run the program's runner makes (engine/step_kernel.hpp)


def entries(cache):
    """The kernel entry points each library in the cache defines."""
    found = {}
    for name in sorted(os.listdir(cache)):
        if name.startswith("kernel-") and name.endswith(".so"):
            symbols = subprocess.run(["nm", "-D", "--defined-only", os.path.join(cache, name)],
                                     capture_output=True, text=True, check=True).stdout.split()
            found[name] = {e for e in (RUN_ENTRY, ORBIT_ENTRY, STEP_ENTRY) if e in symbols}
    return found


# Fresh caches of their own (0700), so that a second run of this test counts only its own.
split_cache = tempfile.mkdtemp(prefix="orbit_split_cache.", dir=work)
trajectory_only = WELL.replace("basin = {}", "final_state = true")
_, log = run(trajectory_only, "well_k_final_state", env_extra={"CONTACTSWEEP_CACHE": split_cache})
found = entries(split_cache)
check("K without a basin map: one kernel, a step kernel, and no orbit built",
      list(found.values()) == [{STEP_ENTRY}] and "orbit kernel" not in log, f"{found}\n{log}")
_, log = run(WELL, "well_k_split", env_extra={"CONTACTSWEEP_CACHE": split_cache})
found = entries(split_cache)
check("K's basin map of fixed points (the energy trap's form): its step kernel alone, no orbit "
      "kernel", sorted(map(sorted, found.values())) == [[STEP_ENTRY], [STEP_ENTRY]]
      and "orbit kernel" not in log, f"{found}\n{log}")
_, log = run(WELL.replace("n = 32", "n = 16").replace('"rk4"', '"contact_splitting4"'),
             "well_k_again", env_extra={"CONTACTSWEEP_CACHE": split_cache})
check("K's next basin map, another grid and another method, builds nothing", "built the" not in log,
      log)
recurrence_cache = tempfile.mkdtemp(prefix="orbit_recurrence_cache.", dir=work)
_, log = run(VDP.replace("n = 32", "n = 8"), "vdp_split",
             env_extra={"CONTACTSWEEP_CACHE": recurrence_cache})
found = entries(recurrence_cache)
orbits = [n for n, e in found.items() if e == {ORBIT_ENTRY}]
check("K's basin map by recurrences: its orbit kernel built beside the runner's, holding the "
      "orbit alone", len(orbits) == 1 and "built the orbit kernel of scene.K beside it" in log
      and all(e in ({ORBIT_ENTRY}, {STEP_ENTRY}) for e in found.values()), f"{found}\n{log}")
strobe_cache = tempfile.mkdtemp(prefix="orbit_strobe_cache.", dir=work)
_, log = run(BUILTIN.replace("basin = {}", "basin = { period = 5.0 }"), "well_builtin_strobe",
             env_extra={"CONTACTSWEEP_CACHE": strobe_cache})
found = entries(strobe_cache)
check("built-in scene on its stroboscopic map: only the orbit kernel is built",
      list(found.values()) == [{ORBIT_ENTRY}] and "built the orbit kernel of scene double_well" in log
      and "built the kernel" not in log, f"{found}\n{log}")
# The built-in double well with lyapunov has a kernel (the tangent's) but no orbit to integrate:
# its attractors are described as without it, to the bit.
with_tangent, _ = run(BUILTIN + "lyapunov = {}\n", "well_builtin_lyapunov")
if builtin and with_tangent:
    a, b = table(builtin), table(with_tangent)
    check("built-in double well with lyapunov: the attractors' description without it, bit for bit",
          all(np.array_equal(a[k], b[k], equal_nan=True) for k in a),
          f"{a['attractor_points'][:, 0]} vs {b['attractor_points'][:, 0]}")

# ---- the chaotic forced Duffing on its stroboscopic map ---------------------------------------
# Reference: tests/reference/duffing_lyapunov.py (scipy DOP853 + variational equations), 8
# trajectories, T = 10^4 each: mean 0.10514, standard deviation 0.0062.
REFERENCE, REFERENCE_SD, REFERENCE_T = 0.10514, 0.0062, 1e4
PERIOD = 2 * math.pi / 1.2
DUFFING = f"""[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"
label = "forced_duffing_chaotic"
delta = 0.3
F = 0.5
Omega = 1.2
[integrator]
method = "contact_splitting4"
h = {PERIOD / 200!r}
t_end = {400 * PERIOD!r}
[grid]
q_0 = {{ from = -2.0, to = 2.0, n = 32 }}
p_0 = {{ from = -2.0, to = 2.0, n = 32 }}
[measures]
basin = {{ period = {PERIOD!r}, cell_size = 0.3, recurrences = 30, locate = 100 }}
"""
chaos, _ = run(DUFFING, "duffing_1x1")
if chaos:
    t = table(chaos)
    window = 256 * PERIOD
    lam = t["attractor_lyapunov"]
    # The finite-time exponent over W scatters as sd sqrt(T_ref / W); the fresh tangent's
    # alignment costs up to 200 lambda / W (as in test_lyapunov.py).
    tolerance = 4 * REFERENCE_SD * math.sqrt(REFERENCE_T / window) + 200 * REFERENCE / window
    check("chaotic Duffing: one attractor, kind chaotic, no period",
          t["attractor_kind"].tolist() == [3] and np.isnan(t["attractor_time_period"][0]),
          f"{t['attractor_kind']} {t['attractor_time_period']}")
    check("chaotic Duffing: lambda_1 vs the DOP853 reference",
          abs(lam[0] - REFERENCE) <= tolerance,
          f"{lam[0]:.5f} vs {REFERENCE} (tolerance {tolerance:.4f})")
    check("chaotic Duffing: 256 distinct section points",
          len(np.unique(t["attractor_points"][0][:, 0])) == 256, "")
    same_bits(chaos, DUFFING, "duffing")

print("FAILED" if runs.failures else "all passed")
sys.exit(1 if runs.failures else 0)
