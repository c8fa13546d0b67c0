#!/usr/bin/python3
"""Attractors followed along a parameter (issue 23, item 3), end to end.

    test_continuation.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

With a scene parameter as the grid's first axis, the attractors at each value are matched to
those of the values before, so an attractor that moves keeps its label:
  * the damped double well written as K (numbered labels), a = 0.8 .. 1.2: exactly two labels
    over the whole map, branch_q at each value = -a, +a (the minima of (q^2 - a^2)^2/2), halves
    of the map by the symmetry (q, p) -> (-q, -p), the file readable by xarray; the built-in
    double well over a keeps its -1/+1 (numbered 1..10 before continuation); with a
    continuation_threshold below the minima's step, ten labels;
  * the magnetic pendulum with the magnets at distance r (0.9 .. 1.3) from the centre: three
    labels, each branch at the minimum of V near its own magnet at every r (V's minima found
    here independently by Newton's method in numpy);
  * the magnets turned by an angle th (0 .. 40 degrees): the two minima left of the centre swap
    their order in q1, so numbering each value's table in sorted order would swap two labels;
    the continuation keeps each label on its magnet;
  * van der Pol's limit cycle over mu (found by recurrences: cell sets matched): one label;
  * the same bits for 1x1, 1x2 and 2x1 on the turning map (its blocks of 256 points straddle
    the values of th: 40 x 40 = 1600 points per value).
"""
import math
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work)
check, run = runs.check, runs.run


TOLERANCE = 1e-3  # measures.basin.tolerance's default: how near its attractor a lane settles

# --- the double well over a ---------------------------------------------------------------------
A_VALUES = [0.8, 0.9, 1.0, 1.1, 1.2]
DW = """
[scene]
{scene}
gamma = 0.2
[integrator]
method = "contact_splitting2"
h = 0.02
t_end = 100.0
[grid]
a = {{ values = [0.8, 0.9, 1.0, 1.1, 1.2] }}
q_0 = {{ from = -3.0, to = 3.0, n = 48 }}
p_0 = {{ from = -3.0, to = 3.0, n = 48 }}
[measures]
basin = {{}}
"""
as_k = run(DW.format(scene='K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"\na = 1.0'), "dw_k_over_a")
if as_k:
    labels = as_k["attractor_label"][...]
    basin = as_k["basin"][...]
    branch = as_k["branch_q"][...]
    check("double well as K over a: two labels over the whole map, every cell decided",
          list(labels) == [1, 2] and set(np.unique(basin)) == {1, 2}, f"{labels}, {np.unique(basin)}")
    expected = np.array([[-a, a] for a in A_VALUES])
    check("double well as K over a: each branch at -a, +a at every a (within the tolerance)",
          branch.shape == (5, 2) and np.allclose(branch, expected, rtol=0, atol=TOLERANCE)
          and np.allclose(as_k["branch_p"][...], 0.0, rtol=0, atol=TOLERANCE), str(branch))
    check("double well as K over a: attractor_q is the branch's point at the first a",
          np.allclose(as_k["attractor_q"][...], [-0.8, 0.8], rtol=0, atol=TOLERANCE))
    fractions = as_k["basin_fraction"][...]
    check("double well as K over a: the two basins are halves at every a (symmetry)",
          np.allclose(fractions, 0.5, rtol=0, atol=1e-12), str(fractions))
    # A lane's label names the well it ends in: at a = 1.2 the right well's basin holds (q, p)
    # = (1.2, 0) (the minimum itself) and the left one (-1.2, 0).
    q0, p0 = as_k["q_0"][...], as_k["p_0"][...]
    i, j = np.argmin(abs(q0 - 1.2)), np.argmin(abs(p0))
    check("double well as K over a: the label at the right minimum is the right branch's",
          basin[4, i, j] == 2 and basin[4, len(q0) - 1 - i, j] == 1)

    # branch_<var> (a, attractor), NaN where absent, reads as netCDF-4 like the other datasets.
    opened = subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                          "test_xarray_open.py"),
                             os.path.join(work, "dw_k_over_a.h5"), "--dims", "a=5", "q_0=48",
                             "p_0=48", "attractor=2", "point=256", "var=2"], capture_output=True, text=True)
    check("double well as K over a: the file with branch_q, branch_p opens in xarray",
          opened.returncode == 0, opened.stdout[-800:] + opened.stderr[-800:])

# continuation_threshold below the minima's step (0.1 per value of a): no branch goes on, ten
# attractors, as without continuation.
apart = run(DW.format(scene='K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"\na = 1.0')
            .replace("basin = {}", "basin = { continuation_threshold = 0.05 }"), "dw_k_apart")
if apart:
    check("double well as K over a, continuation_threshold = 0.05 < the step 0.1: ten labels",
          list(apart["attractor_label"][...]) == list(range(1, 11)), str(apart["attractor_label"][...]))

builtin = run(DW.format(scene='name = "double_well"\na = 1.0'), "dw_builtin_over_a")
if builtin:
    check("built-in double well over a: the wells keep -1/+1 (the scene's rule)",
          list(builtin["attractor_label"][...]) == [-1, 1]
          and set(np.unique(builtin["basin"][...])) == {-1, 1}
          and builtin.attrs["basin_labels"].startswith("the sign of q"),
          f"{builtin['attractor_label'][...]}, {builtin.attrs.get('basin_labels')}")

# --- the magnetic pendulum: magnets moved out (r) and turned (th) -------------------------------
W, D = 0.5, 0.3
ANGLES = (0.0, 2 * math.pi / 3, 4 * math.pi / 3)
magnet_terms = " - ".join(
    f"1/sqrt((q1 - r*cos(th + {a!r}))^2 + (q2 - r*sin(th + {a!r}))^2 + d^2)" for a in ANGLES)
MP = f"""
[scene]
K = "(p1^2 + p2^2)/2 + w^2*(q1^2 + q2^2)/2 - {magnet_terms} - gamma*z"
w = {W}
d = {D}
gamma = 0.2
r = 1.0
th = 0.0
[integrator]
method = "contact_splitting4"
h = 0.02
t_end = 100.0
[grid]
{{axis}} = {{{{ values = {{values}} }}}}
q1_0 = {{{{ from = -2.0, to = 2.0, n = {{n}} }}}}
q2_0 = {{{{ from = -2.0, to = 2.0, n = {{n}} }}}}
[measures]
basin = {{{{}}}}
"""


def minima(r, th):
    """V's minimum near each magnet, by Newton's method from the magnet."""
    magnets = [np.array([r * math.cos(th + a), r * math.sin(th + a)]) for a in ANGLES]
    found = []
    for m in magnets:
        q = m.copy()
        for _ in range(100):
            g, h = W * W * q.copy(), W * W * np.eye(2)
            for x in magnets:
                d = q - x
                s = d @ d + D * D
                g += d * s ** -1.5
                h += np.eye(2) * s ** -1.5 - 3 * np.outer(d, d) * s ** -2.5
            q = q - np.linalg.solve(h, g)
        found.append(q)
    return found  # in the order of the magnets


def follows_magnets(f, values, at):
    """Each label's branch sits at the minimum of one magnet, the same magnet at every value."""
    q = np.stack([f["branch_q1"][...], f["branch_q2"][...]], axis=-1)  # (value, attractor, 2)
    owner = None
    for k, v in enumerate(values):
        m = minima(*at(v))
        nearest = [int(np.argmin([np.max(abs(q[k, a] - x)) for x in m])) for a in range(q.shape[1])]
        error = max(np.max(abs(q[k, a] - m[nearest[a]])) for a in range(q.shape[1]))
        if error > TOLERANCE or (owner is not None and nearest != owner):
            return False, f"value {v}: branches {q[k]} vs minima {m}"
        owner = nearest
    return True, ""


R_VALUES = [0.9, 1.0, 1.1, 1.2, 1.3]
moved = run(MP.format(axis="r", values=R_VALUES, n=48), "mp_over_r")
if moved:
    check("magnetic pendulum over the magnets' distance r: three labels over the whole map",
          list(moved["attractor_label"][...]) == [1, 2, 3]
          and set(np.unique(moved["basin"][...])) == {1, 2, 3})
    ok, detail = follows_magnets(moved, R_VALUES, lambda r: (r, 0.0))
    check("magnetic pendulum over r: each branch at its magnet's minimum at every r", ok, detail)

TH_VALUES = [0.0, 0.17453292519943295, 0.3490658503988659, 0.5235987755982988,
             0.6981317003914655]  # 0, 10, 20, 30, 40 degrees
turned = run(MP.format(axis="th", values=TH_VALUES, n=48), "mp_over_th")
if turned:
    # The test means something: sorted by (q1, q2), the two minima left of the centre swap.
    order = [np.lexsort((np.array(minima(1.0, th))[:, 1].round(6), np.array(minima(1.0, th))[:, 0].round(6)))
             for th in TH_VALUES[:2]]
    check("turning the magnets swaps two minima in sorted order (what per-value numbering would follow)",
          list(order[0]) != list(order[1]), str(order))
    check("magnetic pendulum over th: three labels over the whole map",
          list(turned["attractor_label"][...]) == [1, 2, 3]
          and set(np.unique(turned["basin"][...])) == {1, 2, 3})
    ok, detail = follows_magnets(turned, TH_VALUES, lambda th: (1.0, th))
    check("magnetic pendulum over th: each label stays on its magnet as the magnets turn", ok, detail)
    fractions = turned["basin_fraction"][...]
    check("magnetic pendulum over th: fractions per value sum to 1 with nothing undecided",
          np.allclose(fractions.sum(axis=1), 1.0, rtol=0, atol=1e-12), str(fractions))

# --- a limit cycle followed along mu: the recurrence mapper's cell sets matched --------------------
VDP = """
[scene]
K = "p1*q2 + p2*(mu*(1 - q1^2)*q2 - q1)"
mu = 1.0
[integrator]
method = "rk4"
h = 0.01
t_end = 500.0
[grid]
mu = { values = [0.8, 1.0, 1.2] }
q1_0 = { from = -3.0, to = 3.0, n = 16 }
q2_0 = { from = -3.0, to = 3.0, n = 16 }
[measures]
basin = { locate = 300 }
"""
cycle = run(VDP, "vdp_over_mu")
if cycle:
    branch = np.stack([cycle["branch_q1"][...], cycle["branch_q2"][...]], axis=-1)[:, 0]
    check("van der Pol over mu: one limit cycle, one label, every cell in its basin",
          list(cycle["attractor_label"][...]) == [1] and cycle["attractor_period"][0] == 0
          and np.all(cycle["basin"][...] == 1), f"{cycle['attractor_label'][...]}")
    # The cell named at each mu lies on that mu's cycle, whose amplitude in q1 is about 2
    # (2.0086 at mu = 1) and never above 2.02 for mu <= 1.2: within half a cell's diagonal.
    check("van der Pol over mu: the branch is found at every mu, inside the cycle's reach",
          branch.shape == (3, 2) and np.all(np.isfinite(branch))
          and np.all(abs(branch[:, 0]) < 2.1), str(branch))

# --- the same bits for any ranks x threads --------------------------------------------------------
outputs = []
for ranks, threads in ((1, 1), (1, 2), (2, 1)):
    name = f"mp_th_split_np{ranks}_t{threads}"
    if run(MP.format(axis="th", values=TH_VALUES, n=40), name, ranks=ranks, threads=threads):
        outputs.append(os.path.join(work, name + ".h5"))
result = subprocess.run([sys.executable, compare, *outputs], capture_output=True, text=True)
check("continuation over th: 1x1, 1x2, 2x1 give the same bits",
      len(outputs) == 3 and result.returncode == 0, result.stdout[-1500:] + result.stderr[-500:])

print(f"{runs.failures} failure(s)")
sys.exit(1 if runs.failures else 0)
