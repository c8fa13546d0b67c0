#!/usr/bin/python3
"""The showcases' claims (issue 23 item 6 and its tests; docs/basins.md, "Showcases"), each against
a closed form or an independent computation, on the showcase specs made small.

    test_showcases.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

* Lorenz by cotangent lift (sweeps/basins_lorenz.toml, 8 x 8 starts, t_end = 1000): one
  attractor, every cell, kind chaotic, and attractor_lyapunov, the finite-time exponent of one
  lane over W = 1000, against the literature's 0.9056 within
    4 sigma_W + 3 / W,
  sigma_W = 0.0049 the spread of finite-time exponents over W = 1000 of 256 trajectories of an
  independent integrator (tests/reference/lorenz_lyapunov.py: classical RK4 in numpy, h = 0.005,
  mean 0.9059; scipy's DOP853 with the variational equations on 12 gives mean 0.9076), and 3 / W
  what a fresh tangent gains or loses while it aligns with the unstable direction (-2.5 .. +3.1
  e-folds over 16 starts on the attractor, DOP853); rk4's own bias at h = 0.01 is O(h^4).
* The forced double-well Duffing written autonomously (sweeps/basins_forced_duffing_autonomous
  .toml, the phase q2 an angle) labels every cell of a 24 x 24 plane as the stroboscopic map
  of the same system (sweeps/basins_forced_duffing.toml) does, attractors matched by their well
  (the sign of q over their samples, no self-reference); both of its attractors are periodic with
  the forcing's period 2 pi / Omega = 5 to within the return's interpolation, O(h^3) = 1.25e-4.
* src/post/plot_showcases.py draws these runs and reports the same agreement.
* Van der Pol's limit cycle and the chaotic forced Duffing (sweeps/basins_van_der_pol.toml,
  sweeps/basins_forced_duffing_chaos.toml, made small): 3 ranks x 1 thread give the bits of
  1 x 1 (1 x 2 and 2 x 1 are in test_attractor_analysis.py and test_recurrence_runs.py).
"""
import os
import subprocess
import sys
import tomllib

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, details=True, compare=compare)  # makes work/, its kernel cache
check = runs.check
SWEEPS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sweeps")


def spec(name, **overrides):
    """sweeps/NAME.toml with top-level keys of its tables replaced ("grid.q_0" -> value text)."""
    with open(os.path.join(SWEEPS, name + ".toml")) as f:
        text = f.read()
    tomllib.loads(text)  # it parses as it stands
    lines = text.splitlines()
    for key, value in overrides.items():
        table, _, field = key.rpartition(".")
        section = None
        for k, line in enumerate(lines):
            stripped = line.strip()
            if stripped.startswith("["):
                section = stripped.strip("[]")
            elif section == table and stripped.split("=")[0].strip() == field:
                lines[k] = f"{field} = {value}"
                break
        else:
            raise KeyError(key)
    return "\n".join(lines) + "\n"


def run(spec_text, name, ranks=0, threads=1):
    return runs.launch(spec_text, name, ranks=ranks, threads=threads)[0]


# ---- Lorenz: the strange attractor and its lambda_1 ----------------------------------------------
LITERATURE, SIGMA_W, W = 0.9056, 0.0049, 1000.0
lorenz = run(spec("basins_lorenz", **{"grid.q1_0": "{ from = -20.0, to = 20.0, n = 8 }",
                                      "grid.q2_0": "{ from = -25.0, to = 25.0, n = 8 }",
                                      "integrator.t_end": repr(W)}), "basins_lorenz")
if lorenz:
    with h5py.File(lorenz, "r") as f:
        basin, kind, lam = f["basin"][...], f["attractor_kind"][...], f["attractor_lyapunov"][...]
        check("Lorenz: one attractor, every cell in its basin",
              kind.shape == (1,) and np.all(basin == f["attractor_label"][0]),
              f"labels {np.unique(basin)}, {kind.shape[0]} attractor(s)")
        check("Lorenz: kind chaotic, no period", kind.tolist() == [3]
              and np.isnan(f["attractor_time_period"][0]), f"{kind} {f['attractor_time_period'][...]}")
        tolerance = 4 * SIGMA_W + 3.0 / W
        check(f"Lorenz: attractor_lyapunov vs the literature's {LITERATURE}",
              abs(lam[0] - LITERATURE) <= tolerance,
              f"{lam[0]:.4f}, off by {lam[0] - LITERATURE:+.4f} (tolerance {tolerance:.4f})")
        points = f["attractor_points"][0]
        check("Lorenz: the samples stay on p = 0 and on the attractor's range (0 < z < 50)",
              np.all(points[:, 3:] == 0.0) and 0 < points[:, 2].min() and points[:, 2].max() < 50,
              f"z in [{points[:, 2].min():.2f}, {points[:, 2].max():.2f}]")

# ---- the forced Duffing, stroboscopic and autonomous ---------------------------------------------
PLANE = "{ from = -2.0, to = 2.0, n = 24 }"
strobe = run(spec("basins_forced_duffing", **{"grid.q_0": PLANE, "grid.p_0": PLANE}), "basins_forced_duffing")
auto = run(spec("basins_forced_duffing_autonomous", **{"grid.q1_0": PLANE, "grid.p1_0": PLANE}),
           "basins_forced_duffing_autonomous")


def wells(f):
    points = f["attractor_points"][...]
    table = {int(l): int(np.sign(points[k, :, 0].mean()))
             for k, l in enumerate(f["attractor_label"][...])}
    return np.vectorize(lambda l: table.get(int(l), 0))(f["basin"][...])


if strobe and auto:
    with h5py.File(strobe, "r") as s, h5py.File(auto, "r") as a:
        ws, wa = wells(s), wells(a)
        check("autonomous Duffing: two attractors, one in each well",
              sorted(set(wa.ravel().tolist())) == [-1, 1] and a["attractor_kind"].shape == (2,),
              f"{a['attractor_label'][...]}")
        check("autonomous Duffing: the stroboscopic map's well on every cell",
              np.array_equal(wa, ws), f"{int((wa != ws).sum())} of {wa.size} cells differ")
        T = a["attractor_time_period"][...]
        check("autonomous Duffing: both periodic, period 2 pi / Omega = 5 within h^3",
              a["attractor_kind"][...].tolist() == [1, 1] and np.all(np.abs(T - 5.0) <= 0.05 ** 3),
              f"kinds {a['attractor_kind'][...]}, periods {T}")

# ---- 3 ranks x 1 thread: the bits of 1 x 1 ---------------------------------------------------------
SMALL = {"basins_van_der_pol": {"grid.q1_0": "{ from = -4.0, to = 4.0, n = 32 }",
                                "grid.q2_0": "{ from = -4.0, to = 4.0, n = 32 }"},
         "basins_forced_duffing_chaos": {"grid.q_0": "{ from = -2.0, to = 2.0, n = 32 }",
                                         "grid.p_0": "{ from = -2.0, to = 2.0, n = 32 }"}}
for name, overrides in SMALL.items():
    text = spec(name, **overrides)
    one = run(text, name)  # 1 x 1, under the name plot_showcases.py reads
    three = run(text, f"{name}_3x1", ranks=3)
    if one and three:
        with h5py.File(one, "r") as f:
            kinds = f["attractor_kind"][...].tolist()
        check(f"{name}: the showcase's attractors at 32 x 32",
              kinds == ([1] if "van_der_pol" in name else [1, 3]), f"kinds {kinds}")
        runs.same_bits(f"{name}: 3x1 has the bits of 1x1", one, three)

# ---- src/post/plot_showcases.py on these runs (the orbit diagram is not run here: skipped) ---------
post = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src", "post", "plot_showcases.py")
figures = os.path.join(work, "figures")
drawn = subprocess.run([sys.executable, post, "--in", work, "--out", figures], capture_output=True,
                       text=True)
pngs = sorted(n for n in os.listdir(figures) if n.endswith(".png")) if os.path.isdir(figures) else []
check("plot_showcases.py draws the four runs and skips the fifth",
      drawn.returncode == 0 and len(pngs) == 4 and "orbit_diagram_duffing: skipped" in drawn.stdout,
      f"exit {drawn.returncode}, {pngs}\n{drawn.stdout}{drawn.stderr[-2000:]}")
check("plot_showcases.py counts the agreeing cells as this test does",
      "agree on 576 of 576 cells" in drawn.stdout, drawn.stdout)

runs.finish()
