#!/usr/bin/python3
"""No non-finite value in a cell marked ok (issue 22, item 9).

    test_nonfinite.py CONTACTSWEEP WORKDIR

A table: every method x {singular at start, undefined along the path, overflow}, on one K whose
parameters pick the case per cell (so each method builds one kernel):

    K = p^2/2 + q^2/2 + log(T - t) + A - g*z,   t from 0 to 2, q = 1, p = 0

  * T = 0:  log(0) = -inf at the initial state: status 4 (K undefined at the initial state),
            every value NaN, nothing integrated;
  * T = 1:  q, p a harmonic oscillator (K_q, K_p, K_z do not see log(T - t)), but K, hence
            z' = K - p K_p and H = lambda K, is undefined from t = 1 on: status 3 (non-finite
            output) with q, p finite;
  * A = 1.7e308, T = 10: K is finite at t = 0 but z' = K - p K_p = A + O(1), so z passes
            DBL_MAX at t = DBL_MAX/A = 1.06: status 3 (overflow), q and p finite;
  * A = 0, T = 10: the control, status 0 with every value finite.

Besides: the issue's two reproductions (Lane-Emden from t_start = 0 with contact_splitting2,
log(q) from q = -1), a trajectory-only run (the non-finite value is in traj_z alone), the
summary line counting each flag, and the status dataset's flag_values/flag_meanings.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

binary, work = sys.argv[1:3]
os.makedirs(work, exist_ok=True)
os.environ.setdefault("CONTACTSWEEP_CACHE", os.path.join(work, "kernel_cache"))
failures = 0
METHODS = ["hybrid_leapfrog", "symmetric_leapfrog", "contact_splitting2", "contact_splitting4",
           "contact_splitting6", "rk4"]
OK, DIVERGED, BREAKDOWN, NON_FINITE, UNDEFINED_AT_START = 0, 1, 2, 3, 4


def check(name, ok, detail=""):
    global failures
    print(f"{'ok  ' if ok else 'FAIL'}  {name}" + (f": {detail}" if detail and not ok else ""))
    failures += not ok


def run(spec_text, name, *extra):
    spec = os.path.join(work, name + ".toml")
    out = os.path.join(work, name + ".h5")
    with open(spec, "w") as f:
        f.write(spec_text)
    result = subprocess.run([binary, "run", spec, "-o", out, "--force", *extra],
                            env=dict(os.environ, OMP_NUM_THREADS="1"), capture_output=True,
                            text=True)
    if result.returncode != 0:
        check(f"{name} runs (exit 0)", False, result.stderr.strip()[-2000:])
        return None, result.stderr
    return h5py.File(out, "r"), result.stderr


def values_of(f):
    """Every float dataset of the file with the grid's shape first: name -> array."""
    shape = f["status"].shape
    return {k: f[k][...] for k in f
            if isinstance(f[k], h5py.Dataset) and f[k].dtype.kind == "f"
            and f[k].shape[:len(shape)] == shape and k not in ("T", "A", "q_0", "t")}


def non_finite_cells(f):
    """Cells (grid indices) holding a non-finite value in any output."""
    shape = f["status"].shape
    bad = np.zeros(shape, dtype=bool)
    for name, v in values_of(f).items():
        bad |= ~np.isfinite(v).reshape(shape + (-1,)).all(axis=-1)
    return bad


def no_ok_cell_non_finite(name, f):
    status = f["status"][...]
    bad = non_finite_cells(f) & (status == OK)
    check(f"{name}: no cell with a non-finite value reads status 0", not bad.any(),
          f"{bad.sum()} such cells")


def summary_counts(log):
    m = re.search(r"flagged: (\d+) diverged, (\d+) integrator breakdown, (\d+) non-finite output, "
                  r"(\d+) K undefined at the initial state", log)
    return tuple(int(x) for x in m.groups()) if m else None


TABLE = """
[scene]
K = "p^2/2 + q^2/2 + log(T - t) + A - g*z"
T = 10.0
A = 0.0
g = 0.0
[initial]
q = 1.0
p = 0.0
[integrator]
method = "{method}"
h = 0.01
t_end = 2.0
[grid]
T = {{ values = [0.0, 1.0, 10.0] }}
A = {{ values = [0.0, 1.7e308] }}
[measures]
final_state = true
"""
# (T, A) -> the flag
EXPECTED = {(0.0, 0.0): UNDEFINED_AT_START, (0.0, 1.7e308): UNDEFINED_AT_START,
            (1.0, 0.0): NON_FINITE, (1.0, 1.7e308): NON_FINITE,
            (10.0, 0.0): OK, (10.0, 1.7e308): NON_FINITE}

for method in METHODS:
    f, log = run(TABLE.format(method=method), f"table_{method}")
    if f is None:
        continue
    status = f["status"][...]
    Ts, As = f["T"][...], f["A"][...]
    for i, T in enumerate(Ts):
        for j, A in enumerate(As):
            case = {0.0: "singular at start", 1.0: "undefined along the path"}.get(
                T, "overflow" if A > 0 else "control")
            want = EXPECTED[(float(T), float(A))]
            check(f"{method}, {case} (T = {T:g}, A = {A:g}): status {want}",
                  status[i, j] == want, f"status {status[i, j]}")
    no_ok_cell_non_finite(method, f)
    # Undefined at the initial state: nothing integrated, nothing but NaN written.
    start = Ts == 0.0
    check(f"{method}: K undefined at the start writes NaN everywhere",
          all(np.isnan(v[start]).all() for v in values_of(f).values()))
    # Undefined along the path and overflow: q, p stay those of the oscillator, finite.
    check(f"{method}: along the path and on overflow q and p stay finite",
          np.isfinite(f["final_q"][1:, :]).all() and np.isfinite(f["final_p"][1:, :]).all())
    # The control cell against the exact solution q = cos t (the method's error at h = 0.01).
    check(f"{method}: the control cell is right (q(2) = cos 2 within 1e-3)",
          abs(f["final_q"][2, 0] - np.cos(2.0)) < 1e-3, f"{f['final_q'][2, 0]}")
    check(f"{method}: the summary counts each flag",
          summary_counts(log) == (0, 0, 3, 2), f"{summary_counts(log)} in {log.strip()[-400:]}")

# The non-finite value in a trajectory alone (no final_state): the samples are checked too.
f, log = run(TABLE.format(method="hybrid_leapfrog").replace("final_state = true",
                                                            "trajectory = { every = 10 }"),
             "trajectory_only")
if f is not None:
    check("trajectory only: the undefined path is flagged", f["status"][1, 0] == NON_FINITE,
          f"status {f['status'][...].tolist()}")
    check("trajectory only: the control reads ok", f["status"][2, 0] == OK)
    no_ok_cell_non_finite("trajectory only", f)

# The reproductions.
LANE_EMDEN = """
[scene]
K = "p^2/2 + q^6/6 - (2/t)*z"
[initial]
q = 1.0
[integrator]
method = "contact_splitting2"
t_start = 0.0
h = 0.01
t_end = 1.0
[measures]
final_state = true
"""
f, log = run(LANE_EMDEN, "lane_emden_t0")
if f is not None:
    check("Lane-Emden from t = 0: K undefined at the initial state (status 4)",
          f["status"][()] == UNDEFINED_AT_START, f"status {f['status'][()]}")
    check("Lane-Emden from t = 0: the summary says so", summary_counts(log) == (0, 0, 0, 1),
          log.strip()[-300:])
LOG_Q = """
[scene]
K = "p^2/2 + log(q) - gamma*z"
gamma = 0.1
[initial]
q = -1.0
[integrator]
method = "hybrid_leapfrog"
h = 0.01
t_end = 1.0
[grid]
q_0 = { values = [-1.0, 1.0] }
[measures]
final_state = true
"""
f, log = run(LOG_Q, "log_q")
if f is not None:
    # From rest at q = 1, q'' = -1/q (less damping) reaches q = 0 at t = sqrt(pi/2) = 1.25 at
    # the earliest: after t_end.
    check("log(q): from q = -1 status 4; from q = 1 (never reaching q = 0 by t_end) status 0",
          f["status"][...].tolist() == [UNDEFINED_AT_START, OK], f"{f['status'][...].tolist()}")
    no_ok_cell_non_finite("log(q)", f)

# The status dataset documents its values (CF flags).
if f is not None:
    st = f["status"]
    check("status: flag_values 0 1 2 3 4 255 and their meanings",
          list(st.attrs["flag_values"]) == [0, 1, 2, 3, 4, 255]
          and st.attrs["flag_meanings"].split() == ["ok", "diverged", "integrator_breakdown",
                                                    "non_finite_output", "k_undefined_at_start",
                                                    "not_computed"],
          f"{st.attrs['flag_values']} {st.attrs['flag_meanings']}")

print(f"{'all checks passed' if failures == 0 else f'{failures} check(s) failed'}")
sys.exit(1 if failures else 0)
