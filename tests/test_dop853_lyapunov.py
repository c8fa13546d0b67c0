#!/usr/bin/python3
"""The lyapunov measure with dop853 (adaptive steps; docs/lyapunov.md, "With an adaptive
method"), end to end through the CLI:

    test_dop853_lyapunov.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

* Damped linear oscillator (built-in scene A), under- and overdamped. On a linear field the
  variational equation is the state's own equation, so a lane started at (1, 1) with the default
  tangent (1, 1) carries the same vector twice through the same stages: lyapunov equals
  (1/T) ln(|y_N| / |y_0|) of its final state to rounding. Then its distance from the exact flow's
  finite-time value (1/T) ln(|e^{AT} v| / |v|) is |ln(|y_N| / |y(T)|)| / T <= eps / T, eps the
  state's relative global error, which the controller keeps proportional to rtol (eps <= 10 rtol
  is checked on the final state itself, with atol far below rtol |y| so that the control is
  relative); so |lyapunov - flow| <= 10 rtol / T, and it falls with rtol. The exact value is
  within ln(cond V)/T of the largest exponent: -gamma/2 underdamped (a complex pair, so the
  spectrum (-gamma/2, -gamma/2) sums to -gamma, the trace of the (q, p) Jacobian, the phase-space
  contraction rate), (-gamma + sqrt(gamma^2 - 4 w^2))/2 overdamped.
* Scene B (K_z = -2 gamma z: z feeds back, the tangent carries dz): the exponent equals the
  growth of the central difference of the final (q, p, z) within its own error.
* Chaotic forced Duffing (K-defined): the mean over 9 lanes agrees with rk4's at h = 0.005 from
  the same points, within four standard errors of the two means plus the transient's share
  (tests/test_lyapunov.py's tolerance); and with tests/reference/duffing_lyapunov.py's reference.
* Same bits for 1x1, 1x2, 2x1 ranks x threads on a forced Duffing basin map (stroboscopic, the
  lanes stopping early, a stop condition) with lyapunov; every other dataset the same bits as without it.
* The stop: scene A's lane from (1, 1) stops where q < 0; its tangent at the stop, read on the
  step's continuous extension, is the interpolated state: lyapunov = (1/t_s) ln(|y(t_s)|/sqrt 2).
* observe_window: ln|v| at the window's ends read on the steps' extension on duals. Scene A
  (its runs share the stop's kernel): underdamped with a stop inside the window, overdamped with
  the window ending at t_end: the windowed exponent is the state's own growth between the ends
  and within 20 rtol / (t_e - t_a) of the exact flow's; the same bits without the trajectory. A
  weakly forced (regular) Duffing (the Duffing's kernels): dop853 at rtol and rtol/100 agrees
  with rk4 within the two methods' error estimates by convergence. The basin map with a window and a stop: the same
  bits on 1x1, 2x1, 1x2 ranks x threads and, lyapunov aside, as without lyapunov; NaN exactly
  where a lane stopped before the window.
  (The Duffing and map specs carry an observe formula for that, unused by the checks above.)
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import chaotic_duffing  # noqa: E402
from contactsweep_runs import Runs, read  # noqa: E402
from damped_oscillator import expm, generator  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True, compare=compare)
check = runs.check

# ---- the damped oscillator: closed forms -------------------------------------------------------
OSCILLATOR = """[scene]
name = "damped_oscillator"
omega = {omega!r}
gamma = {gamma!r}
[integrator]
method = "dop853"
rtol = {rtol!r}
atol = {atol!r}
h = 0.1
t_end = {t_end!r}
[grid]
q_0 = {{ values = [1.0] }}
[initial]
p = 1.0
[measures]
final_state = {{ vars = ["q", "p"] }}
lyapunov = {{}}
"""
T = 40.0
v0 = np.array([1.0, 1.0])
for label, omega, gamma in [("underdamped", 1.0, 0.1), ("overdamped", 1.0, 3.0)]:
    a = generator(omega, gamma)
    w, vecs = np.linalg.eig(a)
    largest = max(w.real)
    exact_end = expm(a * T) @ v0
    flow = math.log(np.linalg.norm(exact_end) / np.linalg.norm(v0)) / T
    bound = math.log(np.linalg.cond(vecs)) / T
    check(f"{label}: the exact flow's finite-time value within ln(cond V)/T of {largest:.4f}",
          abs(flow - largest) <= bound, f"{flow:.6f}, bound {bound:.3g}")
    gaps = {}
    for rtol in (1e-6, 1e-9):
        # atol: 1e-6 rtol |y(T)|, so that sk = atol + rtol |y| is rtol |y| to 1e-6 all the way.
        atol = 1e-6 * rtol * np.linalg.norm(exact_end)
        f = runs.run(OSCILLATOR.format(omega=omega, gamma=gamma, rtol=rtol, atol=atol, t_end=T),
                     f"oscillator_{label}_{rtol:.0e}")
        if not f:
            continue
        lyap, q, p = (f[n][...].ravel()[0] for n in ("lyapunov", "final_q", "final_p"))
        y = np.array([q, p])
        own = math.log(np.linalg.norm(y) / np.linalg.norm(v0)) / T
        eps = np.linalg.norm(y - exact_end) / np.linalg.norm(exact_end)
        gap = abs(lyap - flow)
        gaps[rtol] = gap
        # Rounding: ~1e-16 relative per operation over a few hundred steps, over T.
        check(f"{label}, rtol {rtol:g}: lyapunov is the state's own growth (same stages, same "
              f"linear field)", abs(lyap - own) <= 1e-12, f"{lyap!r} vs {own!r}")
        check(f"{label}, rtol {rtol:g}: the state's relative error eps <= 10 rtol",
              eps <= 10 * rtol, f"eps = {eps:.3g} = {eps / rtol:.3g} rtol")
        check(f"{label}, rtol {rtol:g}: |lyapunov - exact finite-time value| <= 10 rtol / T",
              gap <= 10 * rtol / T, f"{gap:.3g} = {gap * T / rtol:.3g} rtol/T")
    if len(gaps) == 2:
        check(f"{label}: the exponent's error falls with rtol (three decades, at least two)",
              gaps[1e-9] <= gaps[1e-6] / 100 or gaps[1e-9] <= 1e-14,
              f"{gaps[1e-6]:.3g} -> {gaps[1e-9]:.3g}")

# ---- scene B, where z feeds back: the tangent (dq, dp, dz) against a central difference ----------
# K = p^2/2 + w^2 q^2/2 - gamma z^2: K_z = -2 gamma z, so the tangent carries dz too. Lanes at
# (q0 +- eps, p0 +- eps) give the central difference D = (y(+) - y(-)) / (2 eps) of the final
# (q, p, z) along the default tangent (1, 1, 0); (1/T) ln(|D| / sqrt 2) is the exponent up to
# the difference's own error, relative: eps^2 (truncation) + 1e-16 / eps (rounding) + the
# steps' dependence on the start that the tangent leaves out (h is not differentiated: each
# step's error, <= rtol, changes with the start, N rtol over N ~ 100 steps): 1e-7 at eps = 1e-5,
# rtol = 1e-10, with a margin of 10 over the largest term.
EPS, Q0, P0, T_B = 1e-5, 0.5, 0.3, 5.0
SCENE_B = f"""[scene]
name = "z2_damping"
[initial]
z = 0.8
[integrator]
method = "dop853"
rtol = 1e-10
atol = 1e-12
h = 0.1
t_end = {T_B!r}
[grid]
q_0 = {{ values = [{Q0 - EPS!r}, {Q0!r}, {Q0 + EPS!r}] }}
p_0 = {{ values = [{P0 - EPS!r}, {P0!r}, {P0 + EPS!r}] }}
[measures]
final_state = {{ vars = ["q", "p", "z"] }}
lyapunov = {{}}
"""
f = runs.run(SCENE_B, "z2_damping_difference")
if f:
    lyap = f["lyapunov"][...]
    y = np.stack([f[n][...] for n in ("final_q", "final_p", "final_z")])
    difference = (y[:, 2, 2] - y[:, 0, 0]) / (2 * EPS)
    by_difference = math.log(np.linalg.norm(difference) / math.sqrt(2.0)) / T_B
    gap = abs(lyap[1, 1] - by_difference)
    check("scene B (z feeds back): lyapunov is the central difference's growth within 1e-7 / T",
          gap <= 1e-7 / T_B, f"{lyap[1, 1]!r} vs {by_difference!r}: {gap:.3g}")

# ---- the chaotic forced Duffing: dop853 against rk4 and the reference ---------------------------
DUFFING_REFERENCE, DUFFING_REFERENCE_STD, DUFFING_REFERENCE_N = (
    chaotic_duffing.REFERENCE, chaotic_duffing.REFERENCE_STD, chaotic_duffing.REFERENCE_N)
DUFFING = chaotic_duffing.SCENE.replace("{", "{{").replace("}", "}}") + """[integrator]
{integrator}
t_end = {t!r}
[grid]
q_0 = {{ from = -0.9, to = 0.9, n = 3 }}
p_0 = {{ from = -0.5, to = 0.5, n = 3 }}
[measures]
final_state = {{ vars = ["q", "p"] }}
observe = {{ E = "p^2/2 - q^2/2 + q^4/4" }}
lyapunov = {{}}
"""
T_DUFFING = 2000.0
means = {}
for method, integrator in [("dop853", 'method = "dop853"\nrtol = 1e-9\nh = 0.1'),
                           ("rk4", 'method = "rk4"\nh = 0.005')]:
    f = runs.run(DUFFING.format(integrator=integrator, t=T_DUFFING), f"duffing_{method}")
    if f:
        means[method] = f["lyapunov"][...].ravel()
if len(means) == 2:
    d, r = means["dop853"], means["rk4"]
    # Four standard errors of the difference of the means; the transient (at most 200 time
    # units at a growth rate off by at most the exponent itself) biases each by up to 200 l / T.
    se = math.hypot(d.std(ddof=1) / math.sqrt(d.size), r.std(ddof=1) / math.sqrt(r.size))
    tolerance = 4 * se + 2 * 200 * DUFFING_REFERENCE / T_DUFFING
    check("forced Duffing: dop853's mean lyapunov agrees with rk4's (h = 0.005)",
          abs(d.mean() - r.mean()) <= tolerance,
          f"{d.mean():.5f} vs {r.mean():.5f} (tolerance {tolerance:.4f}, {d.size} lanes)")
    tolerance = (4 * math.hypot(d.std(ddof=1) / math.sqrt(d.size),
                                DUFFING_REFERENCE_STD / math.sqrt(DUFFING_REFERENCE_N))
                 + 200 * DUFFING_REFERENCE / T_DUFFING)
    check("forced Duffing: dop853's mean lyapunov vs the DOP853 + variational reference",
          abs(d.mean() - DUFFING_REFERENCE) <= tolerance,
          f"{d.mean():.5f} vs {DUFFING_REFERENCE} (tolerance {tolerance:.4f})")

# ---- ranks and threads; the other datasets unchanged -------------------------------------------
# A basin map on the stroboscopic map (samples from the steps' dense output), early stop.
MAP = """[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"
delta = 0.25
F = 0.1
Omega = 1.2566370614359172
[integrator]
method = "dop853"
rtol = 1e-7
h = 0.1
t_end = 150.0
[grid]
q_0 = { from = -2.0, to = 2.0, n = 24 }
p_0 = { from = -2.0, to = 2.0, n = 20 }
[measures]
final_state = { vars = ["q", "p"] }
observe = { E = "p^2/2 - q^2/2 + q^4/4" }
basin = { period = 5.0 }
stop = { when = "q > 1.5" }
"""
outputs = []
for ranks, threads in ((1, 1), (1, 2), (2, 1)):
    out, _ = runs.launch(MAP + "lyapunov = {}\n", f"map_np{ranks}_t{threads}", ranks=ranks,
                         threads=threads)
    if out:
        outputs.append(out)
runs.same_bits("forced Duffing basin map with lyapunov: 1x1, 1x2, 2x1 give the same bits",
               *outputs, count=3)
plain, _ = runs.launch(MAP, "map_without")
if outputs and plain:
    names = ("final_q", "final_p", "basin", "attractor_q", "attractor_p", "stop_time")
    with_l, without = read(outputs[0], *names), read(plain, *names)
    check("final state, basin and attractors: the same bits with and without lyapunov",
          all(np.array_equal(x, y, equal_nan=True) for x, y in zip(with_l, without)))
    (lyap,) = read(outputs[0], "lyapunov")
    (stop_time,) = read(outputs[0], "stop_time")
    # Every lane settles on a period-T orbit (the map's two attractors are stable cycles) or
    # stops: its exponent over [t_start, the settling or stop time] is finite, negative on
    # average; NaN exactly where the lane stopped at t_start (q_0 > 1.5: no interval).
    at_start = stop_time == 0.0
    later = ~at_start
    check("basin map with a stop: lanes stop later and at t_start; the exponent NaN exactly "
          "at t_start, finite elsewhere, negative on average (stable cycles)",
          (np.isfinite(stop_time) & later).any() and at_start.any()
          and np.isnan(lyap[at_start]).all() and np.isfinite(lyap[later]).all()
          and lyap[later].mean() < 0,
          f"{(np.isfinite(stop_time) & later).sum()} stopped later, {at_start.sum()} at t_start, "
          f"mean {lyap[later].mean():.4f}")

# ---- the stop: the tangent at the stop's time, on the step's continuous extension --------------
# Scene A from (1, 1), stopping where q < 0 first holds: as above the tangent (1, 1) is the
# state, so lyapunov over [0, stop_time] is (1/t_s) ln(|y(t_s)| / sqrt 2), y(t_s) the final state
# (the state interpolated at the stop), to rounding; and t_s is the closed form's first zero of
# q within 10 rtol.
# (observe, here unused: the kernel of the window's runs below, which have the same formulas.)
OBSERVE_STOP_A = 'observe = { E = "p^2/2 + q^2/2" }\nstop = { when = "q < 0" }\n'
STOP_A = OSCILLATOR.format(omega=1.0, gamma=0.1, rtol=1e-9, atol=1e-15, t_end=10.0) + OBSERVE_STOP_A
f = runs.run(STOP_A, "oscillator_stop")
if f:
    lyap, q, p, t_s = (f[n][...].ravel()[0] for n in ("lyapunov", "final_q", "final_p",
                                                       "stop_time"))
    own = math.log(math.hypot(q, p) / math.sqrt(2.0)) / t_s
    w_d = math.sqrt(1.0 - 0.1**2 / 4)
    # q(t) = e^{-gt/2} (cos w_d t + (1 + g/2) / w_d sin w_d t): its first zero
    t_zero = (math.pi - math.atan(w_d / (1.0 + 0.05))) / w_d
    check("stop: lyapunov over [0, stop_time] is the interpolated state's own growth",
          abs(lyap - own) <= 1e-12 and abs(t_s - t_zero) <= 10 * 1e-9,
          f"{lyap!r} vs {own!r}; t_s {t_s!r} vs {t_zero!r}")

# ---- observe_window: ln|v| at the window's ends from the steps' extension on duals ------------
# Scene A from (1, 1), window [t_a, t_b] (the runs' observe and stop as the stop's run above: one
# kernel): the tangent (1, 1) is the state through the same stages and the same extension, so
# the windowed exponent is the state's own growth ln(|y(t_e)| / |y(t_a)|) / (t_e - t_a), y(t_a)
# the trajectory's sample there (read on the same extension), y(t_e) the final state, t_e = t_b
# or the stop, to rounding. Each end's ln|y| is off the exact flow's by at most its relative
# error eps (checked <= 10 rtol), so the exponent is within (eps_a + eps_e) / (t_e - t_a) <=
# 20 rtol / (t_e - t_a) of the exact flow's value over [t_a, t_e]. Underdamped, the stop (q < 0,
# t_s = 2.38) ends the interval inside the window [0.5, 10]; overdamped from (1, 1) q stays
# positive, and the window [5, 20] ends at t_end: the last step's end. Without the trajectory
# (the window's samples every nominal step) the marks are the same: the same bits.
RTOL_W, H_W, EVERY_W = 1e-9, 0.1, 5
for label, omega, gamma, t_a, t_b, stops in [("underdamped", 1.0, 0.1, 0.5, 10.0, True),
                                             ("overdamped", 1.0, 3.0, 5.0, 20.0, False)]:
    a = generator(omega, gamma)
    y_a = expm(a * t_a) @ v0
    atol = 1e-6 * RTOL_W * np.linalg.norm(expm(a * t_b) @ v0)
    base = OSCILLATOR.format(omega=omega, gamma=gamma, rtol=RTOL_W, atol=atol, t_end=t_b) + \
        OBSERVE_STOP_A + f"observe_window = {{ from = {t_a!r}, to = {t_b!r} }}\n"
    f = runs.run(base + f"trajectory = {{ every = {EVERY_W} }}\n", f"window_{label}")
    g = runs.run(base, f"window_{label}_every_step")
    if not (f and g):
        continue
    lyap, q, p, t_s = (f[n][...].ravel()[0] for n in ("lyapunov", "final_q", "final_p",
                                                       "stop_time"))
    check(f"window, {label}: the lane {'stops inside the window' if stops else 'never stops'}",
          (t_a < t_s < t_b) if stops else math.isnan(t_s), f"stop_time {t_s!r}")
    t_e = t_s if stops else t_b
    k_a = round(t_a / (EVERY_W * H_W))
    s_a, s_e = np.array([f["traj_q"][...].ravel()[k_a], f["traj_p"][...].ravel()[k_a]]), np.array([q, p])
    own = math.log(np.linalg.norm(s_e) / np.linalg.norm(s_a)) / (t_e - t_a)
    check(f"window, {label}: lyapunov is the state's own growth over [{t_a}, {t_e:.6g}]",
          abs(lyap - own) <= 1e-12, f"{lyap!r} vs {own!r}: {abs(lyap - own):.3g}")
    y_e = expm(a * t_e) @ v0
    eps_a = np.linalg.norm(s_a - y_a) / np.linalg.norm(y_a)
    eps_e = np.linalg.norm(s_e - y_e) / np.linalg.norm(y_e)
    check(f"window, {label}: the states' relative errors at the ends <= 10 rtol",
          max(eps_a, eps_e) <= 10 * RTOL_W, f"{eps_a:.3g}, {eps_e:.3g}")
    flow = math.log(np.linalg.norm(y_e) / np.linalg.norm(y_a)) / (t_e - t_a)
    gap, tolerance = abs(lyap - flow), 20 * RTOL_W / (t_e - t_a)
    check(f"window, {label}: |lyapunov - exact flow's value over [t_a, t_e]| <= 20 rtol / (t_e - t_a)",
          gap <= tolerance, f"{lyap!r} vs {flow!r}: {gap:.3g} (tolerance {tolerance:.3g}, "
          f"{gap * (t_e - t_a) / RTOL_W:.3g} rtol/(t_e - t_a))")
    whole = math.log(np.linalg.norm(y_e) / np.linalg.norm(v0)) / t_e
    check(f"window, {label}: not the value over [0, t_e] (by far more than the tolerance)",
          abs(lyap - whole) > 100 * tolerance, f"{lyap!r} vs {whole!r}")
    check(f"window, {label}: the same bits without a trajectory (every nominal step a sample)",
          np.array_equal(g["lyapunov"][...], f["lyapunov"][...]),
          f"{g['lyapunov'][...].ravel()[0]!r} vs {lyap!r}")

# ---- observe_window on a regular forced Duffing: dop853 against rk4 ----------------------------
# The Duffing above (the same kernels) forced weakly, F = 0.1, delta = 0.25: its 9 lanes settle
# on stable cycles. Window [30, 150] (whole steps of both h: the same t_a), ending at t_end. On a
# nonlinear field the tangent's error is not the state's: its local error (uncontrolled, the
# derivative of the state's) adds up over the window's steps, ~ rtol each, so it is estimated by
# convergence, as rk4's. rk4 (order 4) at h and h/2: |l_{h/2} - l| ~ |l_h - l_{h/2}| / 15;
# dop853 (error ~ rtol) at rtol and rtol / 100: |l_rtol - l| ~ |l_rtol - l_{rtol/100}|; each
# taken twice. Measured: dop853's error at rtol 1e-9 is ~90 rtol / (t_b - t_a).
RTOL_R, T_A_R, T_R = 1e-9, 30.0, 150.0
REGULAR = DUFFING.replace("delta = 0.3", "delta = 0.25").replace("F = 0.5", "F = 0.1") + \
    f"observe_window = {{{{ from = {T_A_R!r}, to = {T_R!r} }}}}\n"
regular = {}
for name, integrator in [("dop853", f'method = "dop853"\nrtol = {RTOL_R!r}\nh = 0.1'),
                         ("dop853_fine", f'method = "dop853"\nrtol = {RTOL_R / 100!r}\nh = 0.1'),
                         ("rk4", 'method = "rk4"\nh = 0.01'),
                         ("rk4_fine", 'method = "rk4"\nh = 0.005')]:
    f = runs.run(REGULAR.format(integrator=integrator, t=T_R), f"window_regular_{name}")
    if f:
        regular[name] = f["lyapunov"][...].ravel()
if len(regular) == 4:
    d, d_fine, r, r_fine = (regular[n] for n in ("dop853", "dop853_fine", "rk4", "rk4_fine"))
    err_d, err_r = 2 * np.abs(d - d_fine), 2 * np.abs(r - r_fine) / 15
    check("regular Duffing: every lane's windowed exponent negative (stable cycles)",
          np.all(d < 0), f"{d.size} lanes, {d.min():.5f} .. {d.max():.5f}")
    for label, x, tolerance in [(f"rtol {RTOL_R:g}", d, err_d + err_r),
                                (f"rtol {RTOL_R / 100:g}", d_fine, err_d / 100 + err_r)]:
        gap = np.abs(x - r_fine)
        check(f"regular Duffing: dop853's windowed exponent at {label} within the two error "
              f"estimates of rk4's at h = 0.005", np.all(gap <= tolerance),
              f"max gap {gap.max():.3g}, max gap / tolerance {(gap / tolerance).max():.3g}; "
              f"dop853 rtol -> rtol/100 up to {np.abs(d - d_fine).max():.3g} "
              f"({np.abs(d - d_fine).max() * (T_R - T_A_R) / RTOL_R:.3g} rtol/(t_b - t_a)), "
              f"rk4 h -> h/2 up to {np.abs(r - r_fine).max():.3g}")

# ---- observe_window with a stop on the stroboscopic map: ranks and threads ---------------------
# The forced Duffing basin map above (its kernel: the same formulas), every lane to t_end, a
# window [2.5, 150] ending at t_end (its lanes stop before t = 4, some inside it): the same bits
# on 1x1, 2x1, 1x2 ranks x threads; NaN exactly where a lane stopped at the window's start or
# before, finite elsewhere.
WINDOW_MAP = MAP.replace("basin = { period = 5.0 }", "basin = { period = 5.0, early_stop = false }") + \
    "observe_window = { from = 2.5, to = 150.0 }\nlyapunov = {}\n"
outputs = []
for ranks, threads in ((1, 1), (2, 1), (1, 2)):
    out, _ = runs.launch(WINDOW_MAP, f"window_map_np{ranks}_t{threads}", ranks=ranks,
                         threads=threads)
    if out:
        outputs.append(out)
runs.same_bits("forced Duffing map with observe_window, stop and lyapunov: 1x1, 2x1, 1x2 give "
               "the same bits", *outputs, count=3)
# Without lyapunov (map_without's kernel): the marks take no step, every other dataset the same.
window_plain, _ = runs.launch(WINDOW_MAP.replace("lyapunov = {}\n", ""), "window_map_without")
if outputs and window_plain:
    names = ("final_q", "final_p", "final_E", "mean_E", "min_E", "max_E", "basin", "stop_time",
             "attractor_q", "attractor_p")
    check("window map: final state, window statistics, basin, stops the same bits with and "
          "without lyapunov", all(np.array_equal(x, y, equal_nan=True) for x, y in
                                  zip(read(outputs[0], *names), read(window_plain, *names))))
if outputs:
    lyap, stop_time = read(outputs[0], "lyapunov", "stop_time")
    stopped = np.isfinite(stop_time)
    before = stopped & (stop_time <= 2.5)
    check("window map: NaN exactly where the lane stopped at the window's start or before",
          before.any() and (stopped & ~before).any() and np.array_equal(np.isnan(lyap), before),
          f"{before.sum()} stopped before, {(stopped & ~before).sum()} inside the window, "
          f"{(~stopped).sum()} never")

runs.finish()
