#!/usr/bin/python3
"""The lyapunov measure end to end (issue 24 item 3; docs/lyapunov.md).

    test_lyapunov.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

* Damped linear oscillator K = p^2/2 + w^2 q^2/2 - gamma z (scene A): the step map of
  contact_splitting2 and of rk4 is a 2x2 matrix M in closed form, so the finite-time exponent of
  the numerical map is (1/T) ln(|M^N v| / |v|) exactly (to rounding); the exact flow's
  (1/T) ln |e^{AT} v|/|v| agrees with it to O(h^order), and lies within ln(cond V)/T of -gamma/2
  (V: A's eigenvectors).
* Van der Pol's limit cycle by cotangent lift: the tangent aligns with the flow F, so
  |T lyapunov| stays below ln(max|F| / min|F|) along the orbit plus ln 2 (the start's
  projection), at T and 4T alike: 0 to within O(1/T).
* Chaotic forced Duffing (delta = 0.3, F = 0.5, Omega = 1.2): the mean over 8 lanes against the
  reference of tests/reference/duffing_lyapunov.py (scipy DOP853 + variational equations), within
  four standard errors of both plus the transient's share.
* Lorenz by cotangent lift: the mean over 8 lanes against the literature's 0.9056.
* Same bits for 1x1, 1x2, 2x1 ranks x threads, and final_q, final_p the same bits as without
  lyapunov.
* Bad input: exit 2, the key named, nothing written.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs, read  # noqa: E402
import chaotic_duffing  # noqa: E402
import damped_oscillator  # noqa: E402
from damped_oscillator import expm, generator, rk4_step  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True, compare=compare)  # makes work/, its kernel cache
check = runs.check


def run(spec_text, name, ranks=0, threads=1, expect=0):
    out, result = runs.launch(spec_text, name, ranks=ranks, threads=threads, expect=expect)
    return out, result.stderr


# ---- damped linear oscillator: closed forms --------------------------------------------------
OMEGA, GAMMA, H, T = 1.0, 0.1, 0.01, 100.0
N = round(T / H)
A = generator(OMEGA, GAMMA)


def step_matrix(method, h):
    if method == "contact_splitting2":  # Z(h/2) V(h/2) T(h) V(h/2) Z(h/2) on (q, p)
        z = np.diag([1.0, np.exp(-GAMMA * h / 2)])
        kick = np.array([[1.0, 0.0], [-h / 2 * OMEGA**2, 1.0]])
        drift = np.array([[1.0, h], [0.0, 1.0]])
        return z @ kick @ drift @ kick @ z
    return rk4_step(A, h)


def growth(matrix, v):
    return np.log(np.linalg.norm(matrix @ v) / np.linalg.norm(v)) / T


def oscillator(method, t_end, lyapunov):
    return damped_oscillator.spec(OMEGA, GAMMA, method, H, t_end, "q_0 = { values = [1.0, -0.5] }",
                                  f'final_state = {{ vars = ["q", "p"] }}\nlyapunov = {lyapunov}')


v = np.array([1.0, 1.0])  # the default start: equal components in q and p
wv, vecs = np.linalg.eig(A)
bound = np.log(np.linalg.cond(vecs)) / T
flow = growth(expm(A * T), v)
check("exact flow within ln(cond V)/T of -gamma/2", abs(flow + GAMMA / 2) <= bound,
      f"{flow} vs {-GAMMA / 2}, bound {bound:.3g}")
for method, order in [("contact_splitting2", 2), ("rk4", 4)]:
    out, _ = run(oscillator(method, T, "{}"),
                 f"oscillator_{method}")
    if out is None:
        continue
    (lyap,) = read(out, "lyapunov")
    numerical = growth(np.linalg.matrix_power(step_matrix(method, H), N), v)
    # Rounding only: N steps of relative error ~1e-16 each in the tangent's norm, over T.
    check(f"{method}: (1/T) ln|M^N v| of the step matrix", np.all(np.abs(lyap - numerical) < 1e-11),
          f"{lyap} vs {numerical}")
    check(f"{method}: exact flow's finite-time value to O(h^{order})",
          np.all(np.abs(lyap - flow) < H**order), f"{lyap} vs {flow}")
    check(f"{method}: same for every initial point (linear map)", lyap[0] == lyap[1], f"{lyap}")

# One direction: the tangent starts in q alone.
out, _ = run(oscillator("rk4", T, '{ vars = ["q"] }'), "oscillator_q")
if out is not None:
    (lyap,) = read(out, "lyapunov")
    numerical = growth(np.linalg.matrix_power(step_matrix("rk4", H), N), np.array([1.0, 0.0]))
    check("vars = [q]: tangent (1, 0)", np.all(np.abs(lyap - numerical) < 1e-11), f"{lyap} vs {numerical}")

# ---- van der Pol's limit cycle: 0 within O(1/T) ------------------------------------------------
VDP = """[scene]
K = "p1*q2 + p2*(mu*(1 - q1^2)*q2 - q1)"
mu = 1.0
[initial]
q2 = 0.0
[integrator]
method = "rk4"
h = 0.01
t_end = {t}
[grid]
q1_0 = {{ values = [2.0, 1.0, 0.5] }}
[measures]
final_state = {{ vars = ["q1", "q2"] }}
trajectory = {{ every = 10 }}
lyapunov = {{ vars = ["q1", "q2"] }}
"""
for t_end in (100.0, 400.0):
    out, _ = run(VDP.format(t=t_end), f"vdp_{int(t_end)}")
    if out is None:
        continue
    lyap, q1, q2 = read(out, "lyapunov", "traj_q1", "traj_q2")
    speed = np.hypot(q2, (1 - q1**2) * q2 - q1)
    limit = (np.log(speed.max(axis=1) / speed.min(axis=1)) + np.log(2.0)) / t_end
    check(f"van der Pol, T = {t_end:g}: |lyapunov| <= ln(max|F|/min|F|)/T + ln 2/T",
          np.all(np.abs(lyap) <= limit), f"{lyap} vs {limit}")

# ---- chaotic forced Duffing: against an independent reference ---------------------------------
DUFFING_REFERENCE, DUFFING_REFERENCE_STD, DUFFING_REFERENCE_T, DUFFING_REFERENCE_N = (
    chaotic_duffing.REFERENCE, chaotic_duffing.REFERENCE_STD, chaotic_duffing.REFERENCE_T,
    chaotic_duffing.REFERENCE_N)
DUFFING = chaotic_duffing.SCENE.replace("{", "{{").replace("}", "}}") + """[integrator]
method = "contact_splitting4"
h = 0.01
t_end = {t}
[grid]
q_0 = {{ from = -0.9, to = 0.9, n = {n} }}
p_0 = {{ from = -0.5, to = 0.5, n = {n} }}
[measures]
final_state = {{ vars = ["q", "p"] }}
{lyapunov}
"""
T_DUFFING = 2000.0
out, _ = run(DUFFING.format(t=T_DUFFING, n=3, lyapunov="lyapunov = {}"), "duffing")
if out is not None:
    (lyap,) = read(out, "lyapunov")
    lyap = lyap.ravel()
    ours = lyap.mean()
    # Four standard errors of each mean; the transient (no more than 200 time units at a growth
    # rate off by at most the exponent itself) biases ours by up to 200·λ/T.
    tolerance = (4 * np.hypot(lyap.std(ddof=1) / np.sqrt(lyap.size),
                              DUFFING_REFERENCE_STD / np.sqrt(DUFFING_REFERENCE_N))
                 + 200 * DUFFING_REFERENCE / T_DUFFING)
    check("forced Duffing: mean lyapunov vs DOP853 + variational reference",
          abs(ours - DUFFING_REFERENCE) <= tolerance,
          f"{ours:.5f} vs {DUFFING_REFERENCE} (tolerance {tolerance:.4f}, {lyap.size} lanes)")

# ---- Lorenz by cotangent lift vs the literature -----------------------------------------------
LORENZ_LITERATURE = 0.9056
LORENZ = """[scene]
K = "p1*(s*(q2 - q1)) + p2*(q1*(r - q3) - q2) + p3*(q1*q2 - b*q3)"
s = 10.0
r = 28.0
b = 2.6666666666666665
[initial]
q2 = 1.0
q3 = 20.0
[integrator]
method = "rk4"
h = 0.01
t_end = 1000.0
[grid]
q1_0 = { from = -1.0, to = 1.0, n = 8 }
[measures]
final_state = { vars = ["q1"] }
lyapunov = { vars = ["q1", "q2", "q3"] }
"""
out, _ = run(LORENZ, "lorenz")
if out is not None:
    (lyap,) = read(out, "lyapunov")
    tolerance = 4 * lyap.std(ddof=1) / np.sqrt(lyap.size) + 20 * LORENZ_LITERATURE / 1000.0
    check("Lorenz: mean lyapunov vs the literature's 0.9056", abs(lyap.mean() - LORENZ_LITERATURE) <= tolerance,
          f"{lyap.mean():.4f} (tolerance {tolerance:.4f}, spread {lyap.std(ddof=1):.4f})")
    print(f"      Lorenz lambda_1 = {lyap.mean():.4f} over {lyap.size} lanes, T = 1000 "
          f"(literature {LORENZ_LITERATURE}: off by {lyap.mean() - LORENZ_LITERATURE:+.4f})")

# ---- ranks and threads: the same bits; the other datasets unchanged ---------------------------
# 32 x 32 points: 4 blocks; 1005 steps leave a remainder for the finisher tile.
SPLIT = DUFFING.format(t=10.05, n=32, lyapunov="lyapunov = {}")
first, _ = run(SPLIT, "split_1x1")
for ranks, threads in [(0, 2), (2, 1)]:
    other, _ = run(SPLIT, f"split_{max(ranks, 1)}x{threads}", ranks=ranks, threads=threads)
    if first and other:
        runs.same_bits(f"{max(ranks, 1)} x {threads} ranks x threads: same bits as 1 x 1", first, other)
plain, _ = run(DUFFING.format(t=10.05, n=32, lyapunov=""), "split_without")
if first and plain:
    a = read(first, "final_q", "final_p")
    b = read(plain, "final_q", "final_p")
    check("final_q, final_p: same bits with and without lyapunov",
          all(np.array_equal(x, y) for x, y in zip(a, b)))
    with h5py.File(plain) as f:
        check("no lyapunov dataset without the measure", "lyapunov" not in f)

# ---- bad input ---------------------------------------------------------------------------------
BAD = oscillator("rk4", 1.0, "@VARS@")
for label, value, key in [
    ("unknown variable", '{ vars = ["q", "x"] }', "measures.lyapunov.vars[1]"),
    ("empty list", "{ vars = [] }", "measures.lyapunov.vars"),
    ("not a list", '{ vars = "q" }', "measures.lyapunov.vars"),
    ("z where z does not feed back", '{ vars = ["z"] }', "measures.lyapunov.vars[0]"),
    ("lambda", '{ vars = ["q", "lambda"] }', "measures.lyapunov.vars[1]"),
    ("unknown key", '{ var = ["q"] }', "measures.lyapunov"),
    ("a number", "3", "measures.lyapunov"),
]:
    name = "bad_" + label.replace(" ", "_")
    out, err = run(BAD.replace("@VARS@", value), name, expect=2)
    check(f"bad input ({label}): exit 2 naming {key}, nothing written",
          out is not None and key in err and not os.path.exists(out), err.strip())

runs.finish()
