#!/usr/bin/python3
"""dop853 (adaptive, per-lane steps) with the measures that sample between its steps (issue 27,
item 4), end to end through the CLI:

    test_dop853_runs.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

  * the stroboscopic map (measures.basin.period), sampled at t_start + k*T from the steps'
    dense output, with an h that does not divide T: a forced linear oscillator settles on its
    closed-form periodic point (A, B*Omega) within rtol, over four decades of rtol, the error
    falling with it;
  * the forced Duffing's basin map (sweeps/basins_forced_duffing.toml, 64 x 64) labels every
    cell as rk4 at h = T/1000 does, but for as many of the reference's boundary cells as lie
    within the rtol-scaled backward error of the boundary (expected count, rounded up); its
    attractors' points agree with rk4's within a multiple of rtol;
  * the same map, the same bits on 1x1, 1x2 and 2x1 ranks x threads;
  * measures.stop on scene A's energy threshold: the exact energy at each lane's stop_time is
    the threshold within 3 rtol (the time located on the step's continuous extension), the final
    state the exact state there, the trajectory NaN after the stop, the error falling with
    rtol, and the same bits on 1x1, 1x2, 2x1;
  * observe_window without a trajectory: every nominal step in the window a sample, the same
    bits as a trajectory's every-step samples give, the exact statistics within 3 rtol.

One K serves every forced run (a linear or a double-well restoring force by its parameters),
so that the test builds two kernels (dop853 and rk4), not four.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True, compare=compare)
check, run = runs.check, runs.run

# q'' + delta q' + a q + b q^3 = F cos(Omega t).
FORCED = """
[scene]
K = "p^2/2 + a*q^2/2 + b*q^4/4 - F*q*cos(Omega*t) - delta*z"
a = {a!r}
b = {b!r}
delta = {delta!r}
F = {F!r}
Omega = {Omega!r}
[integrator]
method = "{method}"
{step}
t_end = {t_end!r}
[grid]
q_0 = {{ from = -2.0, to = 2.0, n = {n} }}
p_0 = {{ from = -2.0, to = 2.0, n = {n} }}
[measures]
basin = {{ period = {period!r}{tolerance} }}
"""


def forced(method, step, n, t_end, period, tolerance="", **scene):
    return FORCED.format(method=method, step=step, n=n, t_end=t_end, period=period,
                         tolerance=tolerance, **scene)


# ---- the stroboscopic map against a closed form -------------------------------------------------
# The forced linear oscillator's one periodic orbit passes through (A, B*Omega) at t = k*T. h =
# 0.1 (the first step) does not divide T = pi. A lane settles when its samples stay within the
# basin tolerance (10 rtol here: the samples jitter at the level of the steps' errors, which rtol
# bounds) and its point is one of its samples: within rtol of the closed form when the global
# error is proportional to rtol (measured: 0.02 to 0.23 rtol from rtol 1e-6 to 1e-10).
W0, DELTA, F, OMEGA = 1.0, 0.3, 0.5, 2.0
den = (W0**2 - OMEGA**2) ** 2 + DELTA**2 * OMEGA**2
A, B = F * (W0**2 - OMEGA**2) / den, F * DELTA * OMEGA / den
LINEAR = dict(a=W0**2, b=0.0, delta=DELTA, F=F, Omega=OMEGA)
T_LIN = 2 * math.pi / OMEGA
errors = {}
for rtol in (1e-6, 1e-8, 1e-10):
    spec = forced("dop853", f"rtol = {rtol!r}\natol = {rtol!r}\nh = 0.1", 12, 400.0, T_LIN,
                  f", tolerance = {10 * rtol!r}", **LINEAR)
    f = run(spec, f"strobe_linear_{rtol:.0e}")
    if not f:
        continue
    q, p = f["attractor_q"][...], f["attractor_p"][...]
    settled = (f["basin"][...] != 0).all() and len(q) >= 1
    error = max(np.abs(q - A).max(), np.abs(p - B * OMEGA).max()) if len(q) else math.inf
    errors[rtol] = error
    check(f"forced linear oscillator, rtol {rtol:g}: every lane settles on (A, B*Omega) within "
          f"rtol", settled and error <= rtol, f"{len(q)} point(s), error {error:.3g} = "
          f"{error / rtol:.3g} rtol")
if len(errors) == 3:
    check("forced linear oscillator: the stroboscopic point's error falls with rtol (four decades "
          "of rtol, at least two of error)", errors[1e-6] / errors[1e-10] > 100,
          f"{errors[1e-6]:.3g} -> {errors[1e-10]:.3g}")

# ---- the forced Duffing's basin map against rk4 -------------------------------------------------
DUFFING = dict(a=-1.0, b=1.0, delta=0.25, F=0.1, Omega=1.2566370614359172)
T = 5.0
dop = run(forced("dop853", "rtol = 1e-8", 64, 400.0, T, **DUFFING), "duffing_dop853")
ref = run(forced("rk4", f"h = {T / 1000!r}", 64, 400.0, T, **DUFFING), "duffing_rk4")
if dop and ref:
    a, b = dop["basin"][...], ref["basin"][...]
    # A cell on the reference's boundary: one of its four neighbours has another label.
    pad = np.pad(b, 1, mode="edge")
    boundary = ((pad[1:-1, :-2] != b) | (pad[1:-1, 2:] != b) | (pad[:-2, 1:-1] != b)
                | (pad[2:, 1:-1] != b))
    wrong = (a != b)
    check("forced Duffing 64 x 64: every cell decided, two attractors as rk4 finds them",
          (a != 0).all() and len(dop["attractor_q"]) == 2 == len(ref["attractor_q"]),
          f"{len(dop['attractor_q'])} and {len(ref['attractor_q'])} attractors")
    # A cell can change label only if its point lies within delta of the basin boundary, delta
    # the two integrations' difference pulled back to t = 0: a run whose local errors are kept
    # below rtol is the exact flow from a point within ~rtol per unit time of its start
    # (backward error; rk4's at h = T/1000 is far smaller), so delta <= 10 rtol t_end with a
    # margin of 10. A boundary cell of side c is then wrong with probability <= delta / c: the
    # allowance is the expected count, rounded up (1 cell here; 0 differ, measured).
    cell = 4.0 / (64 - 1)
    delta = 10 * 1e-8 * 400.0
    allowed = math.ceil(boundary.sum() * delta / cell)
    check("forced Duffing: dop853's labels are rk4's (h = T/1000) but on at most "
          "boundary * delta / cell of its boundary cells",
          not (wrong & ~boundary).any() and wrong.sum() <= allowed,
          f"{wrong.sum()} cells differ, {(wrong & ~boundary).sum()} off the boundary "
          f"({boundary.sum()} boundary cells, {allowed} allowed)")
    # Points: samples within the tolerance (1e-6, the default) of the cycle; rk4's error at h =
    # 0.005 is ~1e-10 and dop853's ~rtol.
    da = np.stack([dop["attractor_q"][...], dop["attractor_p"][...]], axis=1)
    ra = np.stack([ref["attractor_q"][...], ref["attractor_p"][...]], axis=1)
    gap = np.abs(da - ra).max() if da.shape == ra.shape else math.inf
    check("forced Duffing: the attractors' points agree with rk4's within twice the basin "
          "tolerance", gap <= 2e-6, f"{gap:.3g}")

    # ---- the same bits on any cut into ranks and threads ---------------------------------------
    spec = forced("dop853", "rtol = 1e-8", 40, 200.0, T, **DUFFING)
    outputs = []
    for ranks, threads in ((1, 1), (1, 2), (2, 1)):
        name = f"duffing_dop853_np{ranks}_t{threads}"
        out, _ = runs.launch(spec, name, ranks=ranks, threads=threads)
        if out:
            outputs.append(out)
    runs.same_bits("forced Duffing with dop853: 1x1, 1x2, 2x1 give the same bits", *outputs,
                   count=3)

# ---- the stop against a closed form -------------------------------------------------------------
# Scene A (q'' + gamma q' + q = 0): E = (p^2 + q^2)/2 falls monotonically (E' = -gamma p^2), so
# "E < E_th" first holds at one time t*, found here on the exact solution by bisection. A dop853
# lane checks the condition after each accepted step and locates the time it first held on the
# step's continuous extension: its stop_time, where the exact E is E_th to the error of the
# state, proportional to rtol (not up to one step late, as a fixed-step method's stop is).
GAMMA, E_TH = 0.1, 0.1
# Scene A's runs: 27 lanes, q_0 x p_0; MEASURES the [measures] section.
SCENE_A = """
[scene]
name = "damped_oscillator"
omega = 1.0
gamma = {gamma!r}
[integrator]
method = "dop853"
rtol = {rtol!r}
atol = {rtol!r}
h = 0.01
t_end = {t_end!r}
[grid]
q_0 = {{ from = 0.6, to = 1.4, n = 9 }}
p_0 = {{ values = [-0.3, 0.0, 0.3] }}
[measures]
"""
STOP = SCENE_A.replace("{t_end!r}", "60.0") + """final_state = true
trajectory = {{ every = 100 }}
stop = {{ when = "0.5*p^2 + 0.5*q^2 < {e_th!r}" }}
"""
OMEGA_A = math.sqrt(1.0 - GAMMA**2 / 4)


def exact_a(t, q0, p0):
    """Scene A's q, p at time t from (q0, p0), omega = 1."""
    e, c, s = np.exp(-GAMMA * t / 2), np.cos(OMEGA_A * t), np.sin(OMEGA_A * t)
    return (e * (q0 * c + (p0 + GAMMA * q0 / 2) / OMEGA_A * s),
            e * (p0 * c - (q0 + GAMMA * p0 / 2) / OMEGA_A * s))


def energy(t, q0, p0):
    q, p = exact_a(t, q0, p0)
    return 0.5 * p * p + 0.5 * q * q


q0 = np.repeat(np.linspace(0.6, 1.4, 9), 3)
p0 = np.tile([-0.3, 0.0, 0.3], 9)
lo, hi = np.zeros_like(q0), np.full_like(q0, 60.0)
for _ in range(80):  # E is monotone: the crossing by bisection, to rounding
    mid = 0.5 * (lo + hi)
    below = energy(mid, q0, p0) < E_TH
    hi, lo = np.where(below, mid, hi), np.where(below, lo, mid)
t_star = hi
stop_errors = {}
for rtol in (1e-6, 1e-9):
    f = run(STOP.format(gamma=GAMMA, rtol=rtol, e_th=E_TH), f"stop_energy_{rtol:.0e}")
    if not f:
        continue
    t_stop = f["stop_time"][...].ravel()
    fq, fp = f["final_q"][...].ravel(), f["final_p"][...].ravel()
    eq, ep = exact_a(t_stop, q0, p0)
    e_gap = np.abs(energy(t_stop, q0, p0) - E_TH).max()
    state_gap = max(np.abs(fq - eq).max(), np.abs(fp - ep).max())
    stop_errors[rtol] = e_gap
    # The state's error is ~1.5 rtol here (measured), so E's ~|y| times that: bounds of 3 and
    # 10 rtol leave margins of 4 and 7.
    check(f"stop, rtol {rtol:g}: every lane stops, the exact E at its stop_time is E_th within "
          f"3 rtol and its final state the exact state there within 10 rtol",
          np.isfinite(t_stop).all() and e_gap <= 3 * rtol and state_gap <= 10 * rtol,
          f"|E - E_th| {e_gap:.3g} = {e_gap / rtol:.3g} rtol, state {state_gap:.3g}, "
          f"|t_stop - t*| up to {np.abs(t_stop - t_star).max():.3g}")
    check(f"stop, rtol {rtol:g}: the final state meets the condition (the first time it held)",
          (0.5 * fp**2 + 0.5 * fq**2 < E_TH).all())
    tq = f["traj_q"][...].reshape(len(q0), -1)
    times = np.arange(tq.shape[1]) * 1.0
    before = times[None, :] <= t_stop[:, None]
    check(f"stop, rtol {rtol:g}: trajectory samples up to the stop, NaN after it",
          np.isfinite(tq[before]).all() and np.isnan(tq[~before]).all())
if len(stop_errors) == 2:
    check("stop: its error falls with rtol (three decades of rtol, at least two of error)",
          stop_errors[1e-6] / stop_errors[1e-9] > 100,
          f"{stop_errors[1e-6]:.3g} -> {stop_errors[1e-9]:.3g}")

outputs = []
for ranks, threads in ((1, 1), (1, 2), (2, 1)):
    name = f"stop_np{ranks}_t{threads}"
    out, _ = runs.launch(STOP.format(gamma=GAMMA, rtol=1e-8, e_th=E_TH), name, ranks=ranks,
                         threads=threads)
    if out:
        outputs.append(out)
runs.same_bits("stop with dop853: 1x1, 1x2, 2x1 give the same bits", *outputs, count=3)

# ---- observe_window without a trajectory ----------------------------------------------------------
# Its samples are every nominal step t_start + n*h in the window, each from the lane's step's
# continuous extension: the same times, values and order of summation as a trajectory with
# every = 1 whose samples the window then reads, so the same bits; and the mean of E over them
# that of the exact E within a multiple of rtol.
WINDOW = SCENE_A.replace("{rtol!r}", "1e-9").replace("{t_end!r}", "20.0") + """observe = {{ E = "0.5*p^2 + 0.5*q^2" }}
observe_window = {{ from = 10.0, to = 20.0 }}
{trajectory}
"""
alone = run(WINDOW.format(gamma=GAMMA, trajectory=""), "window_alone")
read = run(WINDOW.format(gamma=GAMMA, trajectory="trajectory = { every = 1 }"), "window_read")
if alone and read:
    same = all(np.array_equal(alone[k][...].view(np.uint64), read[k][...].view(np.uint64))
               for k in ("mean_E", "min_E", "max_E", "final_E"))
    check("observe_window without trajectory: mean, min, max of E the same bits as a trajectory's "
          "every-step samples give", same)
    times = 0.01 * np.arange(1000, 2001)
    exact = energy(times[None, :], q0[:, None], p0[:, None])
    gaps = [np.abs(alone[k][...].ravel() - f(exact, axis=1)).max()
            for k, f in (("mean_E", np.mean), ("min_E", np.min), ("max_E", np.max))]
    check("observe_window without trajectory: mean, min, max of E those of the exact E within "
          "3 rtol", max(gaps) <= 3e-9, f"{[f'{g:.2g}' for g in gaps]}")

runs.finish()
