#!/usr/bin/python3
"""The lyapunov measure with measures.stop and measures.observe_window (issue 24; docs/lyapunov.md,
"Over which interval").

    test_lyapunov_stop.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

Damped linear oscillator K = p^2/2 + w^2 q^2/2 - gamma z (scene A, rk4): the step map is the 2x2
matrix M = Taylor polynomial of degree 4 of hA, so the exponent over steps [n_a, n_e] is
ln(|M^n_e v| / |M^n_a v|) / ((n_e - n_a) h) exactly (to rounding), v = (1, 1).
* stop "q < 0" from rest: stop_time within one step after the closed-form first zero of q,
  t* = (pi - atan(2 w_d / gamma)) / w_d; the exponent over [0, stop_time] equals the matrix
  power's, and the exact flow's e^{A T} to O(h^4).
* observe_window [20, 70] without a trajectory (every step a sample) and with one (every = 7:
  the window's ends rounded inwards to samples): the exponent over the window's first and last
  sample, against the matrix powers; the exact flow's value over the window within
  ln(cond V)/T_w of -gamma/2.
* window and stop together: a stop inside the window ends the interval there; a stop before the
  window leaves NaN.
* Forced Duffing with observe, observe_window, stop and lyapunov all on: the same bits for 1 x 1,
  1 x 2 and 2 x 1 ranks x threads, and every other dataset the same bits as without lyapunov.
"""
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs, read  # noqa: E402
import damped_oscillator  # noqa: E402
from damped_oscillator import expm, generator, rk4_step  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True, compare=compare)
check = runs.check


def run(spec_text, name, ranks=0, threads=1):
    return runs.launch(spec_text, name, ranks=ranks, threads=threads)[0]


OMEGA, GAMMA, H = 1.0, 0.1, 0.01
A = generator(OMEGA, GAMMA)
M = rk4_step(A, H)
V0 = np.array([1.0, 1.0])
W_D = math.sqrt(OMEGA**2 - GAMMA**2 / 4)
T_ZERO = (math.pi - math.atan(2 * W_D / GAMMA)) / W_D  # first zero of q from (q, p) = (q0, 0)


def numerical(n_a, n_e):
    """The rk4 map's exponent over steps [n_a, n_e]."""
    va = np.linalg.matrix_power(M, n_a) @ V0
    ve = np.linalg.matrix_power(M, n_e) @ V0
    return math.log(np.linalg.norm(ve) / np.linalg.norm(va)) / ((n_e - n_a) * H)


def flow(t_a, t_e):
    """The exact flow's exponent over [t_a, t_e]."""
    va, ve = expm(A * t_a) @ V0, expm(A * t_e) @ V0
    return math.log(np.linalg.norm(ve) / np.linalg.norm(va)) / (t_e - t_a)


def oscillator(t_end, window="", stop="", trajectory=""):
    return damped_oscillator.spec(OMEGA, GAMMA, "rk4", H, t_end, "q_0 = { values = [1.0, 2.0] }", f"""\
final_state = {{ vars = ["q", "p"] }}
observe = {{ E = "p^2/2 + q^2/2" }}
{window}
{stop}
{trajectory}
lyapunov = {{}}""")


STOP = 'stop = { when = "q < 0" }'

# ---- stop alone: the exponent over [0, stop_time] ----------------------------------------------
out = run(oscillator(100.0, stop=STOP), "stop")
if out:
    lyap, stop_time = read(out, "lyapunov", "stop_time")
    check("stop_time within one step after the closed-form first zero of q",
          np.all((stop_time >= T_ZERO) & (stop_time <= T_ZERO + H)), f"{stop_time} vs {T_ZERO}")
    n_s = round(stop_time[0] / H)
    ours = numerical(0, n_s)
    check("stopped lane: exponent over [0, stop_time] = (1/T) ln|M^N v|/|v|",
          np.all(np.abs(lyap - ours) < 1e-11), f"{lyap} vs {ours} (N = {n_s})")
    exact = flow(0.0, n_s * H)
    check("stopped lane: the exact flow's finite-time value to O(h^4)",
          np.all(np.abs(lyap - exact) < 10 * H**4), f"{lyap} vs {exact}")
    check("stopped lane: not the value over [0, t_end]",
          abs(lyap[0] - numerical(0, 10000)) > 1e-3, f"{lyap[0]} vs {numerical(0, 10000)}")

# ---- window alone: the exponent over the window's first and last sample -----------------------
WINDOW = "observe_window = { from = 20.0, to = 70.0 }"
for label, trajectory, n_a, n_b in [("every step", "", 2000, 7000),
                                    ("trajectory every 7", "trajectory = { every = 7 }", 2002, 7000)]:
    out = run(oscillator(100.0, window=WINDOW, trajectory=trajectory), "window_" + label.replace(" ", "_"))
    if not out:
        continue
    (lyap,) = read(out, "lyapunov")
    ours = numerical(n_a, n_b)
    check(f"window ({label}): exponent over steps [{n_a}, {n_b}] of the matrix powers",
          np.all(np.abs(lyap - ours) < 1e-11), f"{lyap} vs {ours}")
    check(f"window ({label}): not the value over [0, t_end]",
          abs(lyap[0] - numerical(0, 10000)) > 1e-6, f"{lyap[0]} vs {numerical(0, 10000)}")
    exact = flow(n_a * H, n_b * H)
    check(f"window ({label}): the exact flow's value over it to O(h^4)",
          np.all(np.abs(lyap - exact) < 10 * H**4), f"{lyap} vs {exact}")
wv, vecs = np.linalg.eig(A)
bound = math.log(np.linalg.cond(vecs)) / 50.0
exact = flow(20.0, 70.0)
check("exact flow over the window within ln(cond V)/T_w of -gamma/2", abs(exact + GAMMA / 2) <= bound,
      f"{exact} vs {-GAMMA / 2}, bound {bound:.3g}")

# ---- window and stop: the stop ends the interval; a stop before the window leaves NaN ---------
out = run(oscillator(100.0, window="observe_window = { from = 0.5, to = 70.0 }", stop=STOP),
          "window_stop")
if out:
    lyap, stop_time = read(out, "lyapunov", "stop_time")
    n_s = round(stop_time[0] / H)
    ours = numerical(50, n_s)
    check("stop inside the window: exponent over [window start, stop_time]",
          np.all(np.abs(lyap - ours) < 1e-11), f"{lyap} vs {ours} (steps 50 .. {n_s})")
# 100 lanes over the phase (q_0, p_0): each stops at its own step, so the tile refills slots at
# different step counts and lanes sharing a tile sit at different steps when the window opens.
# The window from step 50, and from step 64, a chunk's first: a lane stopping in that chunk is
# stepped again from the chunk's snapshot, where its tangent's mark at the window's start was
# set at the end of the chunk before (rerun_begin clearing it as well went unseen with 50).
for t_a, n_a in ((0.5, 50), (0.64, 64)):
    many = oscillator(100.0, window=f"observe_window = {{ from = {t_a}, to = 70.0 }}", stop=STOP).replace(
        "q_0 = { values = [1.0, 2.0] }", "q_0 = { from = 0.1, to = 1.0, n = 10 }\np_0 = { from = -1.0, to = 1.0, n = 10 }")
    out = run(many, f"window_stop_phases_{n_a}")
    if not out:
        continue
    lyap, stop_time = read(out, "lyapunov", "stop_time")
    lyap, stop_time = lyap.ravel(), stop_time.ravel()
    n_s = np.rint(stop_time / H).astype(int)
    expected = np.array([numerical(n_a, n) if n > n_a else np.nan for n in n_s])
    late = n_s > n_a
    check(f"100 phases, window from step {n_a}: stop times spread over more than a chunk, "
          f"some in the chunk after step {n_a}",
          n_s.max() - n_s.min() > 64 and np.any((n_s > n_a) & (n_s <= n_a + 32)),
          f"{n_s.min()} .. {n_s.max()} steps")
    check(f"100 phases, window from step {n_a}: each lane's exponent over [window start, its stop] "
          f"(NaN: stopped before)",
          np.array_equal(np.isnan(lyap), ~late) and np.all(np.abs(lyap[late] - expected[late]) < 1e-11),
          f"max deviation {np.nanmax(np.abs(lyap - expected)):.3g}, {late.sum()} lanes in the window")
out = run(oscillator(100.0, window=WINDOW, stop=STOP), "window_after_stop")
if out:
    lyap, status = read(out, "lyapunov", "status")
    check("stop before the window: NaN, the lane not flagged", np.all(np.isnan(lyap)) and np.all(status == 0),
          f"{lyap}, status {status}")

# ---- all three measures on: ranks and threads, and every other dataset without lyapunov -------
# 32 x 32 points of the forced Duffing, 1005 steps (a remainder for the finisher tile); lanes
# leaving |q| < 1.3 stop at any step of a chunk.
DUFFING = """[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"
delta = 0.3
F = 0.5
Omega = 1.2
[integrator]
method = "contact_splitting4"
h = 0.01
t_end = 10.05
[grid]
q_0 = { from = -1.2, to = 1.2, n = 32 }
p_0 = { from = -0.8, to = 0.8, n = 32 }
[measures]
final_state = { vars = ["q", "p"] }
observe = { E = "p^2/2 - q^2/2 + q^4/4" }
observe_window = { from = 2.0, to = 9.0 }
stop = { when = "q > 1.3 or q < -1.3" }
{lyapunov}
"""
first = run(DUFFING.replace("{lyapunov}", "lyapunov = {}"), "all_1x1")
if first:
    lyap, stop_time = read(first, "lyapunov", "stop_time")
    stopped = ~np.isnan(stop_time)
    inside = stopped & (stop_time > 2.0)
    check("some lanes stop inside the window, some never: the test covers both",
          inside.sum() > 10 and (~stopped).sum() > 10, f"{inside.sum()} inside, {(~stopped).sum()} never")
    check("stopped before the window: NaN; the rest finite",
          np.all(np.isnan(lyap[stopped & (stop_time <= 2.0)])) and np.all(np.isfinite(lyap[~stopped | inside])))
for ranks, threads in [(0, 2), (2, 1)]:
    other = run(DUFFING.replace("{lyapunov}", "lyapunov = {}"), f"all_{max(ranks, 1)}x{threads}",
                ranks=ranks, threads=threads)
    if first and other:
        runs.same_bits(f"all three measures, {max(ranks, 1)} x {threads} ranks x threads: same bits as 1 x 1",
                       first, other)
plain = run(DUFFING.replace("{lyapunov}", ""), "all_without")
if first and plain:
    with h5py.File(first) as f, h5py.File(plain) as g:
        names = sorted(set(g) - {"lyapunov"})
        differ = [n for n in names if f[n][()].tobytes() != g[n][()].tobytes()]
        check("every other dataset the same bits with and without lyapunov", not differ and "lyapunov" not in g,
              f"differ: {differ}")

runs.finish()
