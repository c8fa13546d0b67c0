#!/usr/bin/python3
"""Basin labels past int8 and the energy trap's box (issue 22, items 10 and 11).

    test_basin_labels.py CONTACTSWEEP WORKDIR

The damped pendulum K = p^2/2 - cos q - gamma*z from rest: E = p^2/2 - cos q never rises, so a
lane starting at q0 in the well (2 pi k - pi, 2 pi k + pi) stays there and ends at its minimum
q = 2 pi k, k = round(q0 / 2 pi). Everything below is compared with that.

  * q0 in [-1000, 1000] (1001 cells, spacing 2 < 2 pi, so every well holds a cell): the minima
    k = round(-1000/2pi) = -159 ... 159, 319 attractors. More than int8's 127: `basin` and
    `attractor_label` are int16, label j+1 is the j-th minimum from the left, each cell's label
    is its own well's and each attractor's cell count is the number of q0 in its well.
  * The double well (built-in, and written as K: two attractors) keeps int8 labels, its label
    rule's -1/+1 and flag_values; at rest |q0| < sqrt 2 (E0 < a^4/2) stays in its own well.
    Without the trap the lane that starts on the saddle settles there by the anchor test; the
    table refuses it (its exact lambda_1 = (-gamma + sqrt(gamma^2 + 8 a^2)) / 2 > 0), so the
    rule still labels the minima -1/+1 and that cell is undecided, basin_undecided saying why.
  * q0 in [-3 pi, 3 pi]: the box around the map, widened by half its width, used to end at
    +-6 pi, minima of V, which put the trap level at the minimum: the trap trapped nothing and
    every lane was integrated until it settled on line. Now the trap is used (root attribute
    `energy_trap` = "used"); every cell whose E0 = -cos q0 is below 0.98 (a level the moved box
    guarantees: its faces, moved in steps of 12 pi/128, land within 0.148 of a maximum, where
    V >= cos(0.148) = 0.989; less the margin h^2 kappa dE = 0.0025 * 1 * 2) is decided at t = 0
    with no step, so the lane-steps integrated are at most those of the cells above 0.98; inner
    cells end at their own well's minimum (k = -1, 0, 1), the same the run without the trap
    reaches; the two end cells, on the maxima +-3 pi, are undecided with the trap (it refuses an
    unstable equilibrium as an attractor) and without it (the anchor test settles them there,
    and the table refuses the maxima: lambda_1 = (-gamma + sqrt(gamma^2 + 4)) / 2 > 0). With gamma in {0, 0.5} as
    a grid axis (a box per parameter set, checked per lane), `energy_trap` says the trap served the damped half and why not the other (no
    dissipation), and the damped half is trapped as above.
"""
import math
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, work = sys.argv[1:3]
runs = Runs(binary, None, work)  # makes work/, its kernel cache; no run under mpiexec here
check = runs.check


def run(spec_text, name):
    """The open output file and the log (None and the log when the run fails)."""
    out, result = runs.launch(spec_text, name, threads=2, quiet=False)
    if out is None:
        return None, result.stderr
    check(f"{name}: no journal left", not os.path.exists(out + ".journal"))
    return h5py.File(out, "r"), result.stderr


PENDULUM = """
[scene]
K = "p^2/2 - cos(q) - gamma*z"
gamma = 0.5
[integrator]
method = "contact_splitting2"
h = 0.05
t_end = {t_end}
[grid]
q_0 = {{ from = {lo!r}, to = {hi!r}, n = {n} }}
[measures]
basin = {basin}
"""


def wells(q0):
    return np.rint(np.asarray(q0) / (2 * math.pi)).astype(int)


# --- item 10: 319 attractors -----------------------------------------------------------------
f, log = run(PENDULUM.format(t_end=150.0, lo=-1000.0, hi=1000.0, n=1001, basin="{}"),
             "pendulum_1000")
if f is not None:
    q0 = f["q_0"][...]
    k = wells(q0)
    minima = np.arange(round(-1000 / (2 * math.pi)), round(1000 / (2 * math.pi)) + 1)
    check("the grid meets every well (319 of them, k = -159 .. 159)",
          len(minima) == 319 and (np.unique(k) == minima).all())
    labels = f["attractor_label"][...]
    check("319 attractors, labelled 1 .. 319", list(labels) == list(range(1, 320)),
          f"{len(labels)} attractors")
    check("basin and attractor_label are int16",
          f["basin"].dtype == np.int16 and f["attractor_label"].dtype == np.int16,
          f"{f['basin'].dtype} {f['attractor_label'].dtype}")
    check("every cell is ok and decided", (f["status"][...] == 0).all()
          and (f["basin"][...] != 0).all())
    if len(labels) == 319:
        check("attractor j+1 is the minimum q = 2 pi k_j, p = 0 (within the tolerance 1e-3)",
              np.allclose(f["attractor_q"][...], 2 * math.pi * minima, atol=1e-3, rtol=0)
              and np.allclose(f["attractor_p"][...], 0.0, atol=1e-3))
        expected = k - minima[0] + 1
        check("each cell's label is its own well's", (f["basin"][...] == expected).all(),
              f"{(f['basin'][...] != expected).sum()} cells differ")
        counts = np.array([(k == m).sum() for m in minima])
        check("attractor_cells counts the cells of each well",
              (f["attractor_cells"][...] == counts).all())

# --- item 10: no check after the work that could run before it ---------------------------------
# A parameter named like a dataset used to be refused by the HDF5 layout after every lane was
# integrated (exit 1, "name 'status' is used twice", journal left, the spec to be changed
# anyway). Now it is bad input before the kernel is built.
for clash in ("status", "attractor_cells"):
    out, r = runs.launch(f"""
[scene]
K = "p^2/2 - cos(q) - {clash}*z"
{clash} = 0.5
[integrator]
h = 0.05
t_end = 10.0
[grid]
{clash} = {{ values = [0.4, 0.5] }}
q_0 = {{ from = -3.0, to = 3.0, n = 8 }}
[measures]
basin = {{}}
""", f"clash_{clash}", quiet=False, expect=2)
    check(f"a parameter named '{clash}': exit 2 before any work, naming it, nothing left",
          out is not None and f"'{clash}'" in r.stderr and "built the kernel" not in r.stderr
          and not os.path.exists(out) and not os.path.exists(out + ".journal"),
          f"exit {r.returncode}: {r.stderr.strip()[-300:]}")

# --- item 10: the double well stays int8 -----------------------------------------------------
DW = """
[scene]
{scene}
[integrator]
method = "contact_splitting2"
h = 0.02
t_end = 100.0
[grid]
q_0 = { from = -1.4, to = 1.4, n = 64 }
[measures]
basin = {}
"""
for name, scene, want in [("double_well", 'name = "double_well"\na = 1.0\ngamma = 0.1', [-1, 1]),
                          ("double_well_k", 'K = "p^2/2 + (q^2 - 1)^2/2 - gamma*z"\ngamma = 0.1',
                           [1, 2])]:
    f, log = run(DW.replace("{scene}", scene), name)
    if f is None:
        continue
    check(f"{name}: basin and attractor_label stay int8",
          f["basin"].dtype == np.int8 and f["attractor_label"].dtype == np.int8)
    check(f"{name}: labels {want}", list(f["attractor_label"][...]) == want)
    q0 = f["q_0"][...]
    check(f"{name}: |q0| < sqrt 2 at rest stays in its own well",
          (f["basin"][...] == np.where(q0 < 0, want[0], want[1])).all())
    if name == "double_well":
        check("double well: flag_values -1 0 1",
              list(f["basin"].attrs["flag_values"]) == [-1, 0, 1]
              and f["basin"].attrs["flag_values"].dtype == np.int8)

# The double well's saddle without the energy trap (which knows (0, 0) is a saddle): the lane
# that starts on it settles there by the anchor test, and the table refuses it as unstable (a
# third attractor at q = 0 would stop the label rule: 1, 2, 3, no flags). The rule labels the
# minima -1/+1, that cell is undecided, and the file and the log say why.
f, log = run(DW.replace("{scene}", 'name = "double_well"\na = 1.0\ngamma = 0.1')
             .replace("n = 64", "n = 65").replace("t_end = 100.0", "t_end = 300.0")
             .replace("basin = {}", "basin = { exact_trap = false }"),
             "double_well_saddle")
if f is not None:
    saddle = (-0.1 + math.sqrt(0.1 ** 2 + 8.0)) / 2  # 1.3651
    why = f"1 settled on an unstable fixed point, refused as an attractor: its exact lambda_1 " \
          f"(K's Jacobian) is positive: (0, 0) with lambda_1 = {saddle:+.4g}"
    check("double well on its saddle: the saddle refused, the minima labelled -1 1",
          list(f["attractor_label"][...]) == [-1, 1] and f["q_0"][32] == 0.0
          and f["basin"][32] == 0 and int((f["basin"][...] == 0).sum()) == 1,
          f"{f['attractor_label'][...]} {f['attractor_q'][...]}")
    check("double well on its saddle: the rule's flags on basin, basin_undecided and the log "
          "say why the saddle's cell is undecided",
          list(f["basin"].attrs.get("flag_values", [])) == [-1, 0, 1]
          and why in f.attrs.get("basin_undecided", "") and why in log,
          f"{dict(f['basin'].attrs)} {f.attrs.get('basin_undecided')}")

# --- item 11: the trap on [-3 pi, 3 pi] --------------------------------------------------------
LO, HI, N, H, T_END = -3 * math.pi, 3 * math.pi, 512, 0.05, 200.0
trap, log_trap = run(PENDULUM.format(t_end=T_END, lo=LO, hi=HI, n=N, basin="{}"), "pendulum_3pi")
online, _ = run(PENDULUM.format(t_end=T_END, lo=LO, hi=HI, n=N, basin="{ exact_trap = false }"),
                "pendulum_3pi_online")
if trap is not None:
    check("[-3 pi, 3 pi]: energy_trap = used", trap.attrs.get("energy_trap") == "used",
          f"{trap.attrs.get('energy_trap')}")
    check("[-3 pi, 3 pi]: the log says the trap was used", "energy trap: used" in log_trap,
          log_trap.strip()[-500:])
    q0 = trap["q_0"][...]
    low = -np.cos(q0) < 0.98
    settle = trap["settle_time"][...]
    check("every cell with E0 < 0.98 is trapped at t = 0", (settle[low] == 0).all(),
          f"{(settle[low] != 0).sum()} of {low.sum()} are not")
    said = re.search(r"; ([0-9.e+]+) lane-steps integrated \(", log_trap)
    steps = round((T_END) / H)
    bound = (~low).sum() * steps
    check(f"lane-steps integrated at most those of the {(~low).sum()} cells above E0 = 0.98 "
          f"({bound / (N * steps):.3f} of the run)",
          said is not None and float(said.group(1)) <= bound,
          f"{said.group(1) if said else log_trap.strip()[-300:]} > {bound}")
if trap is not None and online is not None:
    check("without the trap: energy_trap says exact_trap = false",
          online.attrs.get("energy_trap") == "not used: measures.basin.exact_trap = false")
    # The end cells sit on the maxima +-3 pi, unstable equilibria between two wells: the search
    # without the trap settles them there and the table refuses them (their exact lambda_1 =
    # (-gamma + sqrt(gamma^2 + 4)) / 2 = 0.781), the trap knows they are maxima of V: undecided
    # either way. Every other cell reaches the same minimum either way.
    inner = np.abs(q0) < 3 * math.pi - 1e-9
    maxima = (-0.5 + math.sqrt(0.5 ** 2 + 4.0)) / 2
    check("[-3 pi, 3 pi]: every inner cell decided, with and without the trap",
          (trap["basin"][...][inner] != 0).all() and (online["basin"][...][inner] != 0).all())
    check("[-3 pi, 3 pi]: without the trap the maxima refused, their two cells undecided",
          (online["basin"][...][~inner] == 0).all()
          and online.attrs.get("basin_undecided", "").startswith(
              "2 cells: 2 settled on an unstable fixed point")
          and f"with lambda_1 = {maxima:+.4g}" in online.attrs.get("basin_undecided", ""),
          f"{online['basin'][...][~inner]} {online.attrs.get('basin_undecided')}")
    check("[-3 pi, 3 pi]: with the trap the two cells on the maxima +-3 pi are undecided",
          (trap["basin"][...][~inner] == 0).all() and (~inner).sum() == 2)
    def reached(f):
        return f["attractor_q"][...][np.abs(f["basin"][...][inner]).astype(int) - 1]
    check("[-3 pi, 3 pi]: each inner cell reaches the same minimum with the trap as without",
          np.allclose(reached(trap), reached(online), atol=1e-3, rtol=0),
          f"{(~np.isclose(reached(trap), reached(online), atol=1e-3, rtol=0)).sum()} cells differ")
    at = trap["attractor_q"][...][trap["basin"][...] - 1]
    check("[-3 pi, 3 pi]: each inner cell ends at its own well's minimum 2 pi k, k = -1, 0, 1",
          np.allclose(at[inner], 2 * math.pi * wells(q0[inner]), atol=1e-3, rtol=0)
          and set(wells(q0[inner])) == {-1, 0, 1})

# Per parameter set: gamma = 0 has no trap (E never falls), gamma = 0.5 has one, in the box
# chosen for it; each lane's box is its own (the per-lane screen of a parameter grid). 60 cells:
# only the end cells sit on maxima (with 64, q0 = -pi and pi are grid points, equilibria too).
N2 = 60
both, log_both = run(PENDULUM.format(t_end=T_END, lo=LO, hi=HI, n=N2, basin="{}")
                     .replace("[grid]", "[grid]\ngamma = { values = [0.0, 0.5] }"), "pendulum_gamma")
if both is not None:
    want = (f"used for {N2} of {2 * N2} cells; not for the others: no dissipation: the "
            f"coefficient k of z in K is not negative, so the energy may rise ({N2} cells)")
    check("gamma in {0, 0.5}: energy_trap says where the trap was used and why not elsewhere",
          both.attrs.get("energy_trap") == want, f"{both.attrs.get('energy_trap')}")
    q0 = both["q_0"][...]
    low = -np.cos(q0) < 0.98
    check("gamma = 0.5: every cell with E0 < 0.98 is trapped at t = 0",
          (both["settle_time"][1, :][low] == 0).all())
    inner = np.abs(q0) < 3 * math.pi - 1e-9
    check("gamma = 0: no inner cell settles (no damping)", (both["basin"][0, :][inner] == 0).all())
    said = re.search(r"; ([0-9.e+]+) lane-steps integrated \(", log_both)
    steps = round(T_END / H)
    bound = (N2 + (~low).sum()) * steps
    check("gamma in {0, 0.5}: lane-steps at most the undamped row's and the damped cells' above 0.98",
          said is not None and float(said.group(1)) <= bound, f"{said and said.group(1)} > {bound}")
    labels = both["basin"][1, :][inner]
    check("gamma = 0.5: each inner cell ends at its own well's minimum",
          (labels > 0).all() and np.allclose(both["attractor_q"][...][labels - 1],
                                             2 * math.pi * wells(q0[inner]), atol=1e-3, rtol=0))

runs.finish()
