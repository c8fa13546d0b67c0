#!/usr/bin/python3
"""The recurrence mapper end to end (issue 23, items 1 and 4).

    test_recurrence_runs.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

Van der Pol's oscillator written as a contact Hamiltonian by cotangent lift,
K = p1*q2 + p2*(mu*(1 - q1^2)*q2 - q1): q' = K_p is q1' = q2, q2' = mu (1 - q1^2) q2 - q1, and
p = 0 is invariant (p' = -K_q is linear in p), so lanes from p = 0 follow van der Pol exactly.
At mu = 1 every orbit but the unstable focus at the origin tends to the one limit cycle. The
32 x 32 grid avoids the origin and is cut into 4 blocks of 256 points (the smallest), so the
candidates of several blocks, and of two ranks, are merged, and:
  * every lane settles by recurrences, on one attractor: label 1 everywhere, one table entry of
    period 0 (found by recurrences), settle_time within the run;
  * the entry's point is the centre of its smallest cell, which is the cell of the cycle's
    lowest q2 (keys run q1 fastest, then q2, p1, p2; p = 0 is one cell): within a cell of the
    cycle's minimum of q2 computed here with scipy's DOP853 (an independent integrator), and p
    at the centre of the cell holding 0;
  * the file is the same bits for 1 x 1, 1 x 2 and 2 x 1 ranks x threads, and (t_end = 300:
    lanes settled and undecided) for a run killed after 2 blocks and resumed on 2 ranks;
  * undecided lanes say why: with t_end too short for `recurrences` revisits every lane is
    "no recurrence by t_end"; with a box the cycle never enters, every lane "left the box"; a
    `period` given for this K without t is named as the likely mistake.
"""
import glob
import os
import subprocess
import sys

import h5py
import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, compare=compare)  # makes work/, its kernel cache
check = runs.check


def run(spec_text, name, ranks=0, threads=1):
    """The output's path and the log (None and "" when the run fails)."""
    out, result = runs.launch(spec_text, name, ranks=ranks, threads=threads, quiet=False)
    return (out, result.stdout + result.stderr) if out else (None, "")


VDP = """
[scene]
K = "p1*q2 + p2*(mu*(1 - q1^2)*q2 - q1)"
label = "van_der_pol"
mu = 1.0
[integrator]
method = "rk4"
h = 0.01
t_end = {t_end}
[grid]
q1_0 = {{ from = -3.0, to = 3.0, n = 32 }}
q2_0 = {{ from = -3.0, to = 3.0, n = 32 }}
[measures]
basin = {basin}
"""
T_END = 500.0
BASIN = "{ locate = 300 }"

# The cycle's lowest q2, by DOP853 after the transient (period 6.6632868593...).
cycle = solve_ivp(lambda t, y: [y[1], (1 - y[0] ** 2) * y[1] - y[0]], (0, 200), [2.0, 0.0],
                  method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
t = np.linspace(150, 200, 200001)
lowest_q2 = cycle.sol(t)[1].min()

out, log = run(VDP.format(t_end=T_END, basin=BASIN), "vdp_1x1")
if out:
    with h5py.File(out, "r") as f:
        basin = f["basin"][...]
        check("every lane on the limit cycle (label 1)", np.all(basin == 1),
              f"labels {np.unique(basin, return_counts=True)}")
        check("one attractor, found by recurrences (period 0)",
              f["attractor_label"].shape == (1,) and f["attractor_period"][0] == 0,
              f"{f['attractor_label'][...]}, periods {f['attractor_period'][...]}")
        settle = f["settle_time"][...]
        check("settle times within the run", np.all((settle >= 0) & (settle < T_END)),
              f"{settle.min()} .. {settle.max()}")
        cell = 12.0 / 100  # the box [-6, 6] (the grid's [-3, 3] widened by half) over 100 cells
        q2 = f["attractor_q2"][0]
        check("the attractor's point is in the cell of the cycle's lowest q2",
              abs(q2 - lowest_q2) <= cell, f"q2 = {q2}, the cycle's lowest {lowest_q2}")
        for p in ("p1", "p2"):
            check(f"its {p} is the centre of the cell holding 0",
                  abs(f["attractor_" + p][0]) <= cell / 2, f"{f['attractor_' + p][0]}")
        check("nothing undecided, nothing to explain", "basin_undecided" not in f.attrs,
              f"{f.attrs.get('basin_undecided')}")
    for ranks, threads in ((0, 2), (2, 1)):
        name = f"vdp_{max(ranks, 1)}x{threads}"
        other, _ = run(VDP.format(t_end=T_END, basin=BASIN), name, ranks=ranks, threads=threads)
        if other:
            runs.same_bits(f"{name} has the bits of 1x1", out, other)

# Killed after its second saved block and resumed on 2 ranks: the blocks loaded from the journal
# hold the mapper's records and reasons compact as the computed ones do (lane_records.hpp), and
# the file, labels and basin_undecided included, is the uninterrupted run's. t_end = 300 leaves
# some lanes settled and some undecided.
MIXED = VDP.format(t_end=300.0, basin=BASIN)
mixed, _ = run(MIXED, "vdp_mixed")
if mixed:
    with h5py.File(mixed, "r") as f:
        basin = f["basin"][...]
        check("t_end = 300: lanes settled and lanes undecided, with reasons",
              0 < np.count_nonzero(basin) < basin.size and "basin_undecided" in f.attrs,
              f"labels {np.unique(basin, return_counts=True)}, {f.attrs.get('basin_undecided')}")
    killed, result = runs.launch(MIXED, "vdp_resumed", env_extra={"CONTACTSWEEP_TEST_KILL": "block:2"},
                                 expect=-9)
    journaled = glob.glob(killed + ".journal/block_*.bin") if killed is not None else []
    check("the killed run left finished blocks in its journal", len(journaled) >= 1,
          f"{len(journaled)} blocks")
    if killed is not None:  # --resume, without the --force every launch passes
        env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
                   OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        resume = subprocess.run([mpiexec, "--oversubscribe", "-np", "2", "--bind-to", "none", binary,
                                 "run", os.path.join(work, "vdp_resumed.toml"), "-o", killed,
                                 "--resume", "--quiet"], env=env, capture_output=True, text=True)
        check("the killed run resumes on 2 ranks", resume.returncode == 0, resume.stderr[-1500:])
        if resume.returncode == 0:
            runs.same_bits("killed after 2 blocks, resumed on 2 ranks: the bits of 1x1", mixed, killed)

# Too short for the recurrences: 30 time units are ~94 looks, fewer than 100 revisits.
short, log = run(VDP.format(t_end=30.0, basin=BASIN), "vdp_short")
if short:
    with h5py.File(short, "r") as f:
        why = f.attrs.get("basin_undecided")
        check("a run too short: every lane 'no recurrence by t_end'",
              np.all(f["basin"][...] == 0) and why.startswith("1024 cells: 1024 no recurrence by t_end"),
              f"{why}")
        check("the log names the reason", "no recurrence by t_end" in log, log[-500:])
# A period given for an autonomous K is named as the likely mistake.
strobe, _ = run(VDP.format(t_end=30.0, basin="{ period = 5.0 }"), "vdp_period")
if strobe:
    with h5py.File(strobe, "r") as f:
        why = f.attrs.get("basin_undecided", "")
        check("period for a K without t: diagnosed",
              "period is given but K does not depend on t" in why, why)
# A box the cycle never enters: every lane is outside from its first samples.
away, _ = run(VDP.format(t_end=T_END, basin="{ locate = 300, box = { q1 = [5.0, 6.0] } }"),
              "vdp_box")
if away:
    with h5py.File(away, "r") as f:
        why = f.attrs.get("basin_undecided")
        check("a box off the cycle: every lane 'left the box'",
              np.all(f["basin"][...] == 0) and why.startswith("1024 cells: 1024 left the box"), f"{why}")

# A chaotic attractor on the stroboscopic map: the forced double-well Duffing
# q'' + 0.3 q' - q + q^3 = 0.5 cos(1.2 t) (its textbook strange attractor). No lane finds a
# cycle of period <= 8; every lane settles by recurrences (cells of 0.25: the attractor's
# section spans ~3 x 2), and the lanes' differing located sets, joined by touching cells over
# 4 blocks, are one attractor, with the same bits on 2 ranks.
DUFFING = """
[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"
label = "forced_duffing_chaotic"
delta = 0.3
F = 0.5
Omega = 1.2
[integrator]
method = "contact_splitting4"
h = 0.02617993877991494   # period / 200
t_end = 6283.185307179586  # 1200 periods
[grid]
q_0 = { from = -2.0, to = 2.0, n = 32 }
p_0 = { from = -2.0, to = 2.0, n = 32 }
[measures]
basin = { period = 5.235987755982989, locate = 300, cell_size = 0.25 }
"""
chaos, _ = run(DUFFING, "duffing_1x1")
if chaos:
    with h5py.File(chaos, "r") as f:
        check("chaotic Duffing: every lane on one attractor found by recurrences",
              np.all(f["basin"][...] == 1) and f["attractor_period"][...].tolist() == [0],
              f"labels {np.unique(f['basin'][...])}, periods {f['attractor_period'][...]}")
    other, _ = run(DUFFING, "duffing_2x1", ranks=2)
    if other:
        runs.same_bits("chaotic Duffing: 2x1 has the bits of 1x1", chaos, other)

runs.finish()
