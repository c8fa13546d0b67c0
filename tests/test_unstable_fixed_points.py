#!/usr/bin/python3
"""An unstable fixed point is no attractor (docs/basins.md, "How attractors are found and
labelled"): a table fixed point whose exact lambda_1 (K's Jacobian) is positive leaves the table
before the labels are final, and the cells that settled on it end undecided.

    test_unstable_fixed_points.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

* Lorenz by cotangent lift (sweeps/basins_lorenz.toml, 5 x 5 starts with q1 = q2 = 0 among them,
  t_end = 1000): the z axis is invariant, so that lane converges to the origin along its stable
  manifold and the anchor test settles it. The origin's exact lambda_1 is the largest eigenvalue
  of Lorenz's Jacobian there, (-(s + 1) + sqrt((s - 1)^2 + 4 s r)) / 2 = 11.8277 at s = 10,
  r = 28: refused. The table holds the strange attractor alone (kind chaotic), every other cell
  in its basin, the origin's cell undecided, and basin_undecided says why, with that value. The
  same bits on 1 x 1, 1 x 2 and 2 x 1.
* The damped double well (sweeps/basins_double_well.toml, 5 x 5 over [-2, 2]^2 with (0, 0)
  among them, t_end = 400) with the energy trap off: the anchor test settles the lane that starts
  on the saddle q = p = 0 there, whose lambda_1 = (-gamma + sqrt(gamma^2 + 8 a^2)) / 2 = 1.3651
  is refused, while the minima +-a (lambda_1 = -gamma/2, exact) are kept. Without the saddle the
  scene's rule labels them -1/+1 (before, "an attractor at q = 0" numbered them 1..3), and every
  cell carries the label the energy trap gives it, which refuses the saddle lane by lane.
  Along gamma in {0.1, 0.2} (a continuation: a table per value), the saddle is refused at each
  value with its own lambda_1 (1.3651, 1.3178), the two branches stay -1/+1, and 2 x 1 ranks
  give the bits of 1 x 1.
"""
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True, compare=compare)
check = runs.check
SWEEPS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sweeps")


def spec(name, replacements):
    """sweeps/NAME.toml with each (old, new) line text replaced (each must be there)."""
    with open(os.path.join(SWEEPS, name + ".toml")) as f:
        text = f.read()
    for old, new in replacements:
        if old not in text:
            raise KeyError(old)
        text = text.replace(old, new)
    return text


def cell(f, q1, q2):
    """The basin label of the grid point (q1, q2) of a 2-D plane."""
    a, b = f["basin"].dims[0][0][...], f["basin"].dims[1][0][...]
    return int(f["basin"][int(np.flatnonzero(a == q1)[0]), int(np.flatnonzero(b == q2)[0])])


# ---- Lorenz: the origin, reached along the z axis ------------------------------------------------
S, R = 10.0, 28.0
ORIGIN = (-(S + 1) + math.sqrt((S - 1) ** 2 + 4 * S * R)) / 2  # 11.8277...
lorenz_text = spec("basins_lorenz", [
    ("q1_0 = { from = -20.0, to = 20.0, n = 64 }", "q1_0 = { from = -20.0, to = 20.0, n = 5 }"),
    ("q2_0 = { from = -25.0, to = 25.0, n = 64 }", "q2_0 = { from = -25.0, to = 25.0, n = 5 }"),
    ("t_end = 4000.0", "t_end = 1000.0")])
outputs = []
for ranks, threads in ((0, 1), (0, 2), (2, 1)):
    out, _ = runs.launch(lorenz_text, f"lorenz_{max(ranks, 1)}x{threads}", ranks=ranks,
                         threads=threads)
    if out:
        outputs.append(out)
if outputs:
    with h5py.File(outputs[0], "r") as f:
        kind, label = f["attractor_kind"][...], f["attractor_label"][...]
        point = np.stack([f[f"attractor_q{k}"][...] for k in (1, 2, 3)], axis=-1)
        check("Lorenz: the origin is not in the table",
              not np.any(np.all(np.abs(point) <= 1e-3, axis=-1)), f"points {point.tolist()}")
        check("Lorenz: the strange attractor alone, kind chaotic", kind.tolist() == [3],
              f"kinds {kind.tolist()}")
        basin = f["basin"][...]
        origin = cell(f, 0.0, 0.0)
        check("Lorenz: the z axis's cell undecided, the other 24 in the strange attractor's basin",
              origin == 0 and int((basin == label[0]).sum()) == 24 and int((basin == 0).sum()) == 1,
              f"labels {basin.tolist()}")
        undecided = f.attrs.get("basin_undecided", "")
        check(f"Lorenz: basin_undecided names the refused origin, lambda_1 = {ORIGIN:+.4g}",
              "1 settled on an unstable fixed point" in undecided
              and f"with lambda_1 = {ORIGIN:+.4g}" in undecided, undecided)
        check("Lorenz: undecided_fraction 1/25", f.attrs["undecided_fraction"] == 1 / 25,
              f"{f.attrs['undecided_fraction']}")
    runs.same_bits("Lorenz: 1 x 2 and 2 x 1 have the bits of 1 x 1", *outputs, count=3)

# ---- the double well: the saddle refused, the minima kept ---------------------------------------
A, GAMMA = 1.0, 0.1
SADDLE = (-GAMMA + math.sqrt(GAMMA ** 2 + 8 * A ** 2)) / 2  # 1.3651...
PLANE = [("from = -3.0, to = 3.0, n = 512", "from = -2.0, to = 2.0, n = 5"),
         ("t_end = 100.0", "t_end = 400.0")]
anchor = runs.run(spec("basins_double_well", PLANE + [("basin = {}", "basin = { exact_trap = false }")]),
                  "double_well_anchor")
trap = runs.run(spec("basins_double_well", PLANE), "double_well_trap")
if anchor and trap:
    check("double well: the minima kept, labelled -1/+1 by the scene's rule",
          anchor["attractor_label"][...].tolist() == [-1, 1]
          and np.all(np.abs(anchor["attractor_q"][...] - [-A, A]) <= 1e-3)
          and anchor.attrs.get("basin_labels", "").startswith("the sign of q"),
          f"labels {anchor['attractor_label'][...]}, q {anchor['attractor_q'][...]}, "
          f"{anchor.attrs.get('basin_labels')}")
    lam = anchor["attractor_lyapunov"][...]
    check("double well: the minima's exact lambda_1 = -gamma/2", np.all(np.abs(lam + GAMMA / 2) <= 1e-14),
          f"{lam}")
    undecided = anchor.attrs.get("basin_undecided", "")
    check(f"double well: the saddle's cell undecided, refused with lambda_1 = {SADDLE:+.4g}",
          cell(anchor, 0.0, 0.0) == 0 and "1 cells: 1 settled on an unstable fixed point" in undecided
          and f"(0, 0) with lambda_1 = {SADDLE:+.4g}" in undecided, undecided)
    a, t = anchor["basin"][...], trap["basin"][...]
    check("double well: the energy trap's label on every cell (its saddle lane undecided too)",
          np.array_equal(a, t), f"{int((a != t).sum())} of {a.size} cells differ")

# ---- along gamma: refused at every value of the continuation axis ------------------------------
along_text = spec("basins_double_well", PLANE + [("basin = {}", "basin = { exact_trap = false }"),
                                                 ("[grid]", "[grid]\ngamma = { values = [0.1, 0.2] }")])
one, _ = runs.launch(along_text, "double_well_along_1x1")
two, _ = runs.launch(along_text, "double_well_along_2x1", ranks=2)
if one:
    with h5py.File(one, "r") as f:
        basin = f["basin"][...]
        undecided = f.attrs.get("basin_undecided", "")
        named = [f"(0, 0) with lambda_1 = {(-g + math.sqrt(g * g + 8 * A ** 2)) / 2:+.4g}"
                 for g in (0.1, 0.2)]
        check("along gamma: two branches -1/+1, the saddle's cell undecided at each gamma alone",
              f["attractor_label"][...].tolist() == [-1, 1]
              and [int(basin[k, 2, 2]) for k in (0, 1)] == [0, 0] and int((basin == 0).sum()) == 2,
              f"labels {f['attractor_label'][...]}, {int((basin == 0).sum())} undecided")
        check("along gamma: basin_undecided names the saddle at each gamma with its lambda_1",
              undecided.startswith("2 cells: 2 settled on an unstable fixed point")
              and all(n in undecided for n in named), undecided)
if one and two:
    runs.same_bits("along gamma: 2 x 1 has the bits of 1 x 1", one, two)

runs.finish()
