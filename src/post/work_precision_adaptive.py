"""dop853 in the work-precision charts (src/post/work_precision.py): an adaptive method has no h
to sweep, so its series runs over rtol (atol = rtol) where the fixed-step methods' run over h.

Trajectories: each work-precision spec with its h axis taken out (the damped oscillator's grid
is then its one initial state), one run per rtol, the error measured as for the fixed-step
methods. Cost: the attempts per trajectory (accepted or rejected, the run's "lane-steps
integrated" over its lanes) times the time per attempt, measured like the fixed-step methods'
time per step (2^20 lanes at rtol = 1e-10, 1 thread, the program's own time minus a one-attempt
run's, medians of 5); force evaluations: 12 per attempt.

Basin maps: the map's spec with method = "dop853" and rtol, timed in the same rounds as the
fixed-step methods (BASIN_RTOLS).
"""
import importlib.util
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np

from safe_output import write_text  # lives next to this script

# The Python module's spec writer (a dict shaped like a spec, as TOML), read from its file: the
# package itself needs the built extension.
_TOML = Path(__file__).resolve().parents[1] / "python" / "contactsweep" / "_toml.py"
_spec = importlib.util.spec_from_file_location("contactsweep_toml", _TOML)
_toml = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_toml)
dumps = _toml.dumps

METHOD = "dop853"
EVALS_PER_ATTEMPT = 12
STYLE = ("tab:brown", "*")
RTOLS = ([1e-5, 1e-7, 1e-9], [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12])
BASIN_RTOLS = ([1e-5, 1e-7], [1e-5, 1e-6, 1e-7, 1e-8])
TIMING_RTOL = 1e-10


def settings(rtol):
    """--set pairs selecting dop853 at rtol (atol = rtol)."""
    return [("integrator.method", f'"{METHOD}"'), ("integrator.rtol", repr(rtol)),
            ("integrator.atol", repr(rtol))]


def without_h_axis(spec_path, out):
    """The spec with its grid's h axis taken out (an adaptive method refuses one), written beside
    the outputs; a grid left empty gets the spec's initial q as its one point."""
    with open(spec_path, "rb") as f:
        spec = tomllib.load(f)
    grid = spec.setdefault("grid", {})
    grid.pop("h", None)
    if not grid:
        grid["q_0"] = {"values": [spec["initial"]["q"]]}
    path = Path(out) / f"adaptive_{Path(spec_path).stem}.toml"
    write_text(path, dumps(spec))
    return path


def run_counted(binary, spec, out, sets):
    """One run on 1 thread: (the program's own time, lane-steps integrated: its attempts)."""
    cmd = [str(binary), "run", str(spec), "-o", str(out), "--force"]
    for key, value in sets:
        cmd += ["--set", f"{key}={value}"]
    proc = subprocess.run(cmd, env=dict(os.environ, OMP_NUM_THREADS="1"), capture_output=True,
                          text=True, stdin=subprocess.DEVNULL)
    t = re.search(r"steps in ([0-9.eE+-]+) s", proc.stderr)
    n = re.search(r"; ([0-9.eE+-]+) lane-steps integrated", proc.stderr)
    # Not said when the attempts equal the nominal t_end / h: points x steps then.
    nominal = re.search(r"\((\d+) points x (\d+) steps", proc.stderr)
    if proc.returncode != 0 or not t or not (n or nominal):
        sys.exit(f"failed (exit {proc.returncode}): {' '.join(cmd)}\n{proc.stderr}")
    return float(t[1]), float(n[1]) if n else float(nominal[1]) * float(nominal[2])


def time_per_attempt(binary, spec, out, lanes, repeats):
    """Seconds per lane-attempt: a run of `lanes` trajectories over the spec's t_end minus a
    one-attempt run of as many (set-up and write), medians of `repeats`. More lanes, not a longer
    t_end, make the run long: a damped lane's attempts hardly grow with t once it has settled."""
    sets = [("grid.q_0", f"{{ from = 0.5, to = 2.0, n = {lanes} }}")] + settings(TIMING_RTOL)
    short = sets + [("integrator.t_end", "1e-3"), ("integrator.h", "1e-3")]
    per = []
    for _ in range(repeats):
        t0, n0 = run_counted(binary, spec, out, short)
        t1, n1 = run_counted(binary, spec, out, sets)
        per.append((t1 - t0) / max(n1 - n0, 1.0))
    return float(np.median(per)), [float(min(per)), float(max(per))]


def trajectories(binary, scene, spec_path, error, out, quick, load):
    """dop853's series on one work-precision scene: error(ds) -> (error per point, H error) of
    a dataset with an h dimension of one value."""
    spec = without_h_axis(spec_path, out)
    lanes, repeats = (65536, 1) if quick else (1 << 20, 5)
    s_per_attempt, spread = time_per_attempt(binary, spec, Path(out) / f"timing_{scene}_{METHOD}.h5",
                                             lanes, repeats)
    rows = []
    for rtol in RTOLS[0 if quick else 1]:
        path = Path(out) / f"wp_{scene}_{METHOD}_rtol{rtol:g}.h5"
        _, attempts = run_counted(binary, spec, path, settings(rtol))
        ds = load(path).expand_dims(h=[0.0])
        err, herr = error(ds)
        per_lane = attempts / ds.status.size
        rows.append({"rtol": rtol, "error": float(np.max(err)), "H_error": float(np.max(herr)),
                     "attempts": per_lane, "time_s": per_lane * s_per_attempt,
                     "evals": per_lane * EVALS_PER_ATTEMPT})
    return {"s_per_attempt": s_per_attempt, "spread": spread, "rows": rows}


def print_trajectories(scene, r):
    print(f"{METHOD} on {scene} ({r['s_per_attempt'] * 1e9:.2f} ns per attempt, range of repeats "
          f"{r['spread'][0] * 1e9:.2f} - {r['spread'][1] * 1e9:.2f}):")
    print(f"{'rtol':>8s}{'error':>12s}{'H error':>12s}{'attempts':>10s}{'time/traj':>12s}")
    for x in r["rows"]:
        print(f"{x['rtol']:8.0e}{x['error']:12.2e}{x['H_error']:12.2e}{x['attempts']:10.0f}"
              f"{x['time_s'] * 1e6:10.2f}us")


def chart_trajectories(axes, r):
    """On the fixed-step chart's time and force-evaluation axes (not on h's)."""
    color, marker = STYLE
    rows = r["rows"]
    e = [x["error"] for x in rows]
    kw = dict(color=color, marker=marker, ms=5, lw=1.2)
    axes[1].loglog([x["time_s"] for x in rows], e,
                   label=f"{METHOD} over rtol: {r['s_per_attempt'] * 1e9:.2f} ns/attempt", **kw)
    axes[2].loglog([x["evals"] for x in rows], e, label=f"{METHOD} over rtol: 12 eval/attempt", **kw)
    axes[0].plot([], [], label=f"{METHOD}: no h (charted over rtol, middle and right)", **kw)


def chart_basins(ax, rows, floor):
    color, marker = STYLE
    f = np.maximum([r["differ"] for r in rows], floor)
    ax.loglog([r["time_s"] for r in rows], f, color=color, marker=marker, ms=5, lw=1.2,
              label=f"{METHOD} (rtol {rows[0]['rtol']:g} … {rows[-1]['rtol']:g})")
