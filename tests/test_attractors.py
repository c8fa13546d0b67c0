#!/usr/bin/python3
"""Basins of any system (issue 11): attractors found, not assumed.

    test_attractors.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

Each check runs real specs and compares with what theory says:
  * the damped double well written as K: the energy trap generalised (critical points of V found
    at set-up) gives the built-in exact trap's labels cell for cell, and the on-line search
    (exact_trap = false) the same basins;
  * the magnetic pendulum: three attractors, at the minima of V (found here independently by
    Newton's method in numpy), with mirror-equal fractions; trap and on-line search agree;
  * labels and table do not depend on ranks or threads (1x1, 1x2, 2x1, 3x1) on its fractal map
    (gamma = 0.08, S_bb > ln 2);
  * a forced linear oscillator: one attractor on the stroboscopic map at its closed form (A, B*Omega),
    each lane's settle_time the time of the sample that opened its settled run, recomputed from
    its samples by the documented cycle search, and a period-2 cycle {(A, B*Omega), (-A, -B*Omega)} when sampled every half period;
  * an undamped oscillator: nothing settles, every label is 0, the table is empty, exit 0.
"""
import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, compare=compare)  # makes work/, its kernel cache
check, run = runs.check, runs.run


def table(f):
    return {k: f[k][...] for k in f if k.startswith("attractor")}


# --- the double well: built-in trap, the generalised trap on K, the on-line search ------------
DW = """
[scene]
{scene}
[integrator]
method = "contact_splitting2"
h = 0.02
t_end = {t_end}
[grid]
q_0 = {{ from = -3.0, to = 3.0, n = 96 }}
p_0 = {{ from = -3.0, to = 3.0, n = 96 }}
[measures]
basin = {basin}
"""
builtin = run(DW.format(scene='name = "double_well"\na = 1.0\ngamma = 0.1', t_end=100, basin="{}"),
              "dw_builtin")
as_k = run(DW.format(scene='K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"\na = 1.0\ngamma = 0.1',
                     t_end=100, basin="{}"), "dw_k")
online = run(DW.format(scene='K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"\na = 1.0\ngamma = 0.1',
                       t_end=200, basin="{ exact_trap = false, tolerance = 0.01 }"), "dw_online")
if builtin and as_k and online:
    trap = builtin["basin"][...]
    check("double well: built-in trap decides every cell", (trap != 0).all())
    t = table(as_k)
    check("double well as K: two attractors, the minima (-1, 0) and (1, 0)",
          list(t["attractor_label"]) == [1, 2] and np.allclose(t["attractor_q"], [-1, 1], atol=1e-9)
          and np.allclose(t["attractor_p"], 0.0), str(t))
    generic = np.where(as_k["basin"][...] == 1, -1, np.where(as_k["basin"][...] == 2, 1, 0))
    check("double well as K: the generalised trap's labels equal the exact trap's, cell for cell",
          (generic == trap).all(), f"{(generic != trap).sum()} cells differ")
    # Not all: the found trap level (saddle V(0) from Newton, margin h²κΔE with κ from a
    # finite-difference Hessian) equals a⁴/2 − 2h²a⁶ only up to rounding, so a lane whose energy
    # lands within that rounding of the level may settle one look later.
    same_time = np.isclose(as_k["settle_time"][...], builtin["settle_time"][...], rtol=0, atol=1e-12)
    check("double well as K: settle times equal the exact trap's (>= 99.9 % of cells)",
          same_time.mean() >= 0.999, f"{same_time.mean()}")
    # The summary counts the steps integrated, not points x steps: the trap stops each lane at
    # its settle time (a look, so a whole number of steps).
    spec = os.path.join(work, "dw_builtin.toml")
    line = subprocess.run([binary, "run", spec, "-o", os.path.join(work, "dw_again.h5"), "--force"],
                          capture_output=True, text=True).stderr + "\n"
    expected = np.rint(builtin["settle_time"][...] / 0.02).sum()
    said = re.search(r"; ([0-9.e+]+) lane-steps integrated", line)
    check("the summary reports the lane-steps integrated, as the settle times add up (3 digits)",
          said is not None and abs(float(said.group(1)) / expected - 1) < 5e-3,
          f"{line.strip()} vs {expected:.4g}")
    found = np.where(online["basin"][...] == 1, -1, np.where(online["basin"][...] == 2, 1, 0))
    check("double well: the on-line search (no trap) finds the same basins",
          (found == trap).all(), f"{(found != trap).sum()} cells differ")
    t = table(online)
    check("double well: the on-line search places the attractors within the tolerance",
          np.allclose(t["attractor_q"], [-1, 1], atol=0.01) and np.allclose(t["attractor_p"], 0, atol=0.01),
          str(t))

# --- the magnetic pendulum --------------------------------------------------------------------
W, D, GAMMA = 0.5, 0.3, 0.2
MAGNETS = [(math.cos(a), math.sin(a)) for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3)]
magnet_terms = " - ".join(f"1/sqrt((q1 - ({x!r}))^2 + (q2 - ({y!r}))^2 + d^2)" for x, y in MAGNETS)
MP = f"""
[scene]
K = "(p1^2 + p2^2)/2 + w^2*(q1^2 + q2^2)/2 - {magnet_terms} - gamma*z"
w = {W}
d = {D}
gamma = {GAMMA}
[integrator]
method = "contact_splitting4"
h = 0.02
t_end = {{t_end}}
[grid]
q1_0 = {{{{ from = -2.0, to = 2.0, n = {{n}} }}}}
q2_0 = {{{{ from = -2.0, to = 2.0, n = {{n}} }}}}
[measures]
basin = {{basin}}
"""


def grad_hess(q):
    g = W * W * q.copy()
    h = W * W * np.eye(2)
    for x, y in MAGNETS:
        r = q - np.array([x, y])
        s = r @ r + D * D
        g += r * s ** -1.5
        h += np.eye(2) * s ** -1.5 - 3 * np.outer(r, r) * s ** -2.5
    return g, h


minima = []
for x, y in MAGNETS:
    q = np.array([x, y])
    for _ in range(100):
        g, h = grad_hess(q)
        q = q - np.linalg.solve(h, g)
    minima.append(q)
minima = sorted(minima, key=lambda m: (round(m[0], 6), round(m[1], 6)))

mp = run(MP.format(t_end=200, n=128, basin="{}"), "mp_trap")
mp_online = run(MP.format(t_end=200, n=128, basin="{ exact_trap = false }"), "mp_online")
if mp and mp_online:
    t = table(mp)
    points = np.stack([t["attractor_q1"], t["attractor_q2"]], axis=1)
    check("magnetic pendulum: three attractors at the minima of V (to 1e-7)",
          len(points) == 3 and np.allclose(points, minima, atol=1e-7), f"{points} vs {minima}")
    f = t["attractor_fraction"]
    check("magnetic pendulum: every cell decided, mirror magnets' fractions equal (to 1 %)",
          (mp["basin"][...] != 0).all() and abs(f[0] - f[1]) < 0.01 and abs(sum(f) - 1) < 1e-12, str(f))
    check("magnetic pendulum: the on-line search gives the trap's labels cell for cell",
          (mp["basin"][...] == mp_online["basin"][...]).all(),
          f"{(mp['basin'][...] != mp_online['basin'][...]).sum()} cells differ")
    t2 = table(mp_online)
    check("magnetic pendulum: on line, the attractors within the tolerance of the minima",
          np.allclose(np.stack([t2["attractor_q1"], t2["attractor_q2"]], axis=1), minima, atol=1e-3))
    for key in ("basin_entropy", "boundary_basin_entropy", "uncertainty_exponent"):
        check(f"magnetic pendulum: {key} reported and in range",
              0.0 < mp.attrs[key] < (math.log(3) if "entropy" in key else 2.0), str(mp.attrs[key]))

    # The engine's S_b and S_bb against the post-processing module's (src/post/basin_entropy.py),
    # written independently: the same boxes of 5 x 5 cells, 0 counted as an outcome.
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src", "post"))
    from basin_entropy import basin_entropy
    reference = basin_entropy(mp["basin"][...], eps=5)
    check("magnetic pendulum: S_b and S_bb equal src/post/basin_entropy.py's (to 1e-12)",
          abs(reference.S_b - mp.attrs["basin_entropy"]) < 1e-12
          and abs(reference.S_bb - mp.attrs["boundary_basin_entropy"]) < 1e-12,
          f"{reference} vs {mp.attrs['basin_entropy']}, {mp.attrs['boundary_basin_entropy']}")

# Same spec, same bits, for any ranks x threads: with the trap on a fractal map (gamma = 0.08:
# S_bb > ln 2, checked), and with the on-line search (gamma = 0.2, where lanes settle by t = 100).
for mode, basin, gamma, t_end in (("trap", "{}", 0.08, 150), ("online", "{ exact_trap = false }", GAMMA, 100)):
    outputs = []
    for ranks, threads in ((1, 1), (1, 2), (2, 1), (3, 1)):
        name = f"mp_split_{mode}_np{ranks}_t{threads}"
        if run(MP.format(t_end=t_end, n=60, basin=basin), name, "--set", f"scene.gamma={gamma}",
               ranks=ranks, threads=threads):
            outputs.append(os.path.join(work, name + ".h5"))
    if mode == "trap" and outputs:
        with h5py.File(outputs[0], "r") as f:
            check("magnetic pendulum at gamma = 0.08: a fractal map (S_bb > ln 2), all decided",
                  f.attrs["boundary_basin_entropy"] > math.log(2) and (f["basin"][...] != 0).all(),
                  str(f.attrs["boundary_basin_entropy"]))
    runs.same_bits(f"magnetic pendulum ({mode}): 1x1, 1x2, 2x1, 3x1 give the same bits", *outputs,
                   count=4)

# --- a forced linear oscillator: its one periodic orbit, in closed form -------------------------
OMEGA0, GAMMA_F, F, OMEGA = 1.0, 0.3, 0.5, 2.0
den = (OMEGA0**2 - OMEGA**2) ** 2 + GAMMA_F**2 * OMEGA**2
A, B = F * (OMEGA0**2 - OMEGA**2) / den, F * GAMMA_F * OMEGA / den
period = 2 * math.pi / OMEGA
FL = f"""
[scene]
K = "p^2/2 + w0^2*q^2/2 - F*q*cos(W*t) - gamma*z"
w0 = {OMEGA0}
gamma = {GAMMA_F}
F = {F}
W = {OMEGA}
[integrator]
method = "contact_splitting4"
h = {period / 256!r}
t_end = {period * 120!r}
[grid]
q_0 = {{ from = -2.0, to = 2.0, n = 12 }}
p_0 = {{ from = -2.0, to = 2.0, n = 12 }}
[measures]
basin = {{ period = {{strobe}}, tolerance = 1e-6 }}
"""
fl = run(FL.replace("{strobe}", repr(period)), "forced_linear")
if fl:
    t = table(fl)
    check("forced linear oscillator: one attractor, a fixed point of the stroboscopic map",
          list(t["attractor_period"]) == [1] and (fl["basin"][...] == 1).all(), str(t))
    check("forced linear oscillator: at (A, B*Omega) to 1e-5 (closed form)",
          abs(t["attractor_q"][0] - A) < 1e-5 and abs(t["attractor_p"][0] - B * OMEGA) < 1e-5,
          f"{t} vs {(A, B * OMEGA)}")
# settle_time on the stroboscopic map: the time of the sample that opened the run that settled
# (docs/basins.md). Recomputed from the lane's samples at t = k*period (a trajectory every
# period of the same map without early stop: the same states, bit for bit) by the cycle search
# as documented: per period m <= 8 a run anchored at m samples, a sample within the tolerance of
# its anchor counts, another starts a new run at the last m samples; `dwell` matches settle it.
def strobe_settle(samples, tolerance, dwell, max_period=8):
    """(period, index of the sample that opened the settled run) of one lane, or (0, None)."""
    runs_ = [None] * (max_period + 1)  # per m: [start, matched]
    for k in range(len(samples)):
        for m in range(1, max_period + 1):
            if k < m - 1:
                continue
            r = runs_[m]
            if r is not None and k >= r[0] + m:
                anchor = samples[r[0] + (k - r[0]) % m]
                if np.max(np.abs(samples[k] - anchor)) <= tolerance:
                    r[1] += 1
                    if r[1] >= dwell:
                        return m, r[0]
                    continue
            runs_[m] = [k - m + 1, 0]
    return 0, None


dwell_periods = 16  # the default dwell on the stroboscopic map
watched = run(FL.replace("{strobe}", repr(period)).replace(
    "tolerance = 1e-6 }", "tolerance = 1e-6, early_stop = false }\ntrajectory = { every = 256 }"),
    "forced_linear_traj")
if fl and watched:
    q, p = watched["traj_q"][...], watched["traj_p"][...]  # (q_0, p_0, sample)
    q, p = q.reshape(-1, q.shape[-1]), p.reshape(-1, p.shape[-1])
    expected = np.full(q.shape[0], np.nan)
    for lane in range(q.shape[0]):
        m, start = strobe_settle(np.stack([q[lane], p[lane]], axis=1), 1e-6, dwell_periods)
        if m:
            expected[lane] = start * period
    got = fl["settle_time"][...].ravel()
    check("forced linear oscillator: every lane settles, its settle_time the opening sample's "
          "time k*period recomputed from its samples (to rounding of k*period)",
          np.isfinite(expected).all() and np.allclose(got, expected, rtol=1e-13, atol=0)
          and len(np.unique(np.round(expected / period))) > 3,
          f"{np.count_nonzero(~np.isclose(got, expected, rtol=1e-13, atol=0))} lanes differ; "
          f"{got[:6]} vs {expected[:6]}")
half = run(FL.replace("{strobe}", repr(period / 2)), "forced_linear_half")
if half:
    t = table(half)
    lead = min((A, B * OMEGA), (-A, -B * OMEGA))
    check("sampled every half period: a period-2 cycle through (-A, -B*Omega) and (A, B*Omega)",
          list(t["attractor_period"]) == [2] and abs(t["attractor_q"][0] - lead[0]) < 1e-5
          and abs(t["attractor_p"][0] - lead[1]) < 1e-5, f"{t} vs {lead}")

# --- nothing settles ---------------------------------------------------------------------------
none = run("""
[scene]
K = "p^2/2 + q^2/2"
[integrator]
h = 0.05
t_end = 50.0
[grid]
q_0 = { from = -1.0, to = 1.0, n = 8 }
p_0 = { from = -1.0, to = 1.0, n = 8 }
[measures]
basin = {}
""", "nothing_settles")
if none:
    check("undamped oscillator: nothing settles, every label 0, an empty table",
          (none["basin"][...] == 0).all() and none["attractor"].shape == (0,)
          and np.isnan(none["settle_time"][...]).all() and none.attrs["undecided_fraction"] == 1.0)

runs.finish()
