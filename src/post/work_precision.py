#!/usr/bin/python3
"""Work-precision of every integrator: error against cost, per trajectory and per basin map.

  work_precision.py --bin build/contactsweep --out out/work_precision [--quick]

1. Trajectories. Runs sweeps/workprecision_damped_oscillator.toml and
   sweeps/workprecision_double_well.toml once per method (--set integrator.method=NAME; the grid's
   h axis gives every step size in one run) and measures the error of the final state at t_end:
   - damped oscillator: against the exact solution (exact_oscillator below): max of |dq|, |dp| over the
     exact amplitude sqrt(q^2 + p^2), |dz| / |z| and |d ln lambda|;
   - double well: against contact_splitting6 at h = 2.5e-4, max over the initial states of |dq|,
     |dp|, |dz| / max(1, |z|) and |d ln lambda|. The reference's own error is estimated by the same
     measure against a run at h / 2 (6th order: the difference is its error within 2 %), printed.
   The observed order is the least-squares slope of log error over log h on the points with
   FIT_LO <= error <= FIT_HI (asymptotic, and well above round-off).
   Cost: a timing run of a large ensemble (65536 trajectories, h = 1/64, steps for about 0.7 s,
   OMP_NUM_THREADS=1, the program's own time, median of 5, minus the median of one-step runs that
   time parsing and the HDF5 write) gives each method's time per trajectory-step on each scene; cost(h) = (t_end / h) * that, and force evaluations = (t_end / h) * evals per step.
   Also: relative error of H = lambda K at t_end (exactly conserved by the flow), and over a long
   run (oscillator, gamma = 0.01, t = 10^4, h = 0.1 and 0.05).
   dop853 (adaptive: no h) is charted over rtol on the time and evaluation axes
   (work_precision_adaptive.py), and on the basin maps below.
2. Basin maps. sweeps/basins_double_well.toml at 512 x 512 cells (t_end = 100, early stop as in
   the spec) per method and step size (whole steps of 100): fraction of cells whose basin differs
   from a fine reference map (contact_splitting6, h = 0.0025; its own differing fraction against
   h / 2 is printed), against the time to compute the map: the program's own end-to-end time
   (set-up, integrate, HDF5 write; OMP_NUM_THREADS=1, median of 5), which leaves out the process
   launch (~0.4 s here, printed).

Writes DIR/*.h5, DIR/work_precision.json (every number below) and the charts
  DIR/workprecision_damped_oscillator.png, DIR/workprecision_double_well.png
      error against h (legend: nominal and observed order), against wall time per trajectory,
      against force evaluations; one line per method;
  DIR/basin_accuracy.png   differing fraction of the basin map against its wall time, and against h;
  DIR/basin_accuracy_magnetic_pendulum.png   the same for sweeps/basins_magnetic_pendulum.toml
      (128 x 128 cells, t_end = 200, reference contact_splitting6 at h = 0.0025).
Prints tables of all numbers. --replot: only redraw the charts from DIR/work_precision.json.
--quick: short timing runs without repeats, a 64 x 64 map at three step sizes with a coarser
reference (about 30 s; for tests). The full run takes about 7 minutes.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from stability_maps import (METHOD_STYLE, load, method_set, methods_table, run, save,  # noqa: E402
                            toml_list)

import matplotlib.pyplot as plt  # noqa: E402  (stability_maps selected the Agg backend)
import work_precision_adaptive as adaptive  # noqa: E402  (dop853's series, over rtol)
from safe_output import write_output  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SWEEPS = ROOT / "sweeps"
SPECS = {"damped_oscillator": SWEEPS / "workprecision_damped_oscillator.toml",
         "double_well": SWEEPS / "workprecision_double_well.toml"}
BASIN_SPEC = SWEEPS / "basins_double_well.toml"
# Error range of the order fit: asymptotic (below FIT_HI), and above round-off (~1e-12 after 2e4
# steps) or, on the double well, 50x above the reference's own error (2e-11, itself round-off).
FIT_HI = 1e-2
FIT_LO = {"damped_oscillator": 1e-10, "double_well": 1e-9}
H_TIMING = 1.0 / 64             # exact in binary, so every step count gives an exact t_end
REF_H_DW = 2.5e-4               # the double-well reference step (the spec's comment)


def spec_of(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def run_timed(binary, spec, out, sets):
    """One run on 1 thread; returns (wall seconds of the command, the program's own end-to-end
    time: set-up, integration, HDF5 write and commit, without process and MPI launch and spec parsing)."""
    cmd = [str(binary), "run", str(spec), "-o", str(out), "--force"]
    for key, value in sets:
        cmd += ["--set", f"{key}={value}"]
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=dict(os.environ, OMP_NUM_THREADS="1"), capture_output=True,
                          text=True, stdin=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    m = re.search(r"steps in ([0-9.eE+-]+) s", proc.stderr)
    if proc.returncode != 0 or not m:
        sys.exit(f"failed (exit {proc.returncode}): {' '.join(cmd)}\n{proc.stderr}")
    return wall, float(m[1])


def median_times(binary, spec, out, sets, repeats):
    """(median wall, median program time) over `repeats` runs."""
    t = np.array([run_timed(binary, spec, out, sets) for _ in range(repeats)])
    return float(np.median(t[:, 0])), float(np.median(t[:, 1]))


# --- errors ---------------------------------------------------------------------------------------

def exact_oscillator(spec, t):
    """Exact (q, p, z, ln lambda, H) of scene A at time t: q'' + gamma q' + omega^2 q = 0,
    ln lambda = ln lambda0 + gamma t, and H = lambda K conserved gives K, hence z."""
    sc, ini = spec["scene"], spec["initial"]
    w, g = sc["omega"], sc["gamma"]
    q0, p0, z0, l0 = ini["q"], ini["p"], ini["z"], ini["lambda"]
    om = np.sqrt(w * w - g * g / 4)
    d = np.exp(-g * t / 2)
    q = d * (q0 * np.cos(om * t) + (p0 + g * q0 / 2) / om * np.sin(om * t))
    p = d * (p0 * np.cos(om * t) - (w * w * q0 + g * p0 / 2) / om * np.sin(om * t))
    k0 = (p0 * p0 + w * w * q0 * q0) / 2 - g * z0
    z = ((p * p + w * w * q * q) / 2 - k0 * np.exp(-g * t)) / g
    return q, p, z, np.log(l0) + g * t, l0 * k0


def error_oscillator(ds, spec):
    """Error per h (NaN where a lane failed) and the relative H error."""
    t = float(ds.attrs["t_end"])
    q, p, z, ll, H = exact_oscillator(spec, t)
    amp = np.hypot(q, p)
    err = np.maximum.reduce([abs(ds.final_q.values - q) / amp, abs(ds.final_p.values - p) / amp,
                             abs(ds.final_z.values - z) / abs(z), abs(ds.final_log_lambda.values - ll)])
    bad = ds.status.values != 0
    err[bad] = np.nan
    herr = abs(ds.final_H.values - H) / abs(H)
    herr[bad] = np.nan
    return err, herr


def error_double_well(ds, ref):
    """Max over the initial states (q_0) of the error against ref (a dataset with one h)."""
    r = ref.isel(h=0)
    parts = [abs(ds.final_q - r.final_q), abs(ds.final_p - r.final_p),
             abs(ds.final_z - r.final_z) / np.maximum(1.0, abs(r.final_z)),
             abs(ds.final_log_lambda - r.final_log_lambda)]
    e = np.maximum.reduce([x.transpose("h", "q_0").values for x in parts]).max(axis=1)
    bad = (ds.status.transpose("h", "q_0").values != 0).any(axis=1)
    e[bad] = np.nan
    # H = lambda K is conserved by the flow: its exact value is the initial one, per q_0.
    H0 = ref.final_H.isel(h=0).values  # reference's H (equal to H(0) to its accuracy)
    herr = (abs(ds.final_H.transpose("h", "q_0").values - H0) / abs(H0)).max(axis=1)
    herr[bad] = np.nan
    return e, herr


def fit_order(h, err, lo):
    ok = np.isfinite(err) & (err >= lo) & (err <= FIT_HI)
    if ok.sum() < 3:
        return np.nan, 0
    return float(np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)[0]), int(ok.sum())


# --- cost per trajectory-step ---------------------------------------------------------------------

def time_per_step(binary, scene, table, out, lanes, target, repeats, quick):
    """{method: timing} with the seconds per trajectory-step of each method on the scene's
    work-precision spec: the program's own time of a long run minus that of a one-step run
    (parsing, set-up, HDF5 write), medians of `repeats`. The repeats go round all methods in
    turn, so a burst of load from other work on the machine does not land on one method only."""
    spec = SPECS[scene]

    def sets(method, steps):
        return [method_set(method), ("grid.h.values", toml_list([H_TIMING])),
                ("integrator.h", repr(H_TIMING)), ("grid.q_0", f"{{ from = 0.5, to = 2.0, n = {lanes} }}"),
                ("integrator.t_end", repr(steps * H_TIMING))]

    path = out / f"timing_{scene}.h5"
    steps = {}
    for m, (_, evals) in table.items():
        if quick:  # no pilot: assume 1 ns per force evaluation
            steps[m] = int(target / (1e-9 * evals * lanes))
        else:
            pilot = 2000
            est = max(run_timed(binary, spec, path, sets(m, pilot))[1]
                      - run_timed(binary, spec, path, sets(m, 1))[1], 1e-3) / (pilot * lanes)
            steps[m] = int(np.clip(target / (est * lanes), 200, 200000))
    one = {m: [] for m in table}
    long = {m: [] for m in table}
    for _ in range(repeats):
        for m in table:
            one[m].append(run_timed(binary, spec, path, sets(m, 1))[1])
            long[m].append(run_timed(binary, spec, path, sets(m, steps[m]))[1])
    res = {}
    for m in table:
        per_step = [(b - a) / ((steps[m] - 1) * lanes) for a, b in zip(one[m], long[m])]
        t_one, t_long = float(np.median(one[m])), float(np.median(long[m]))
        res[m] = {"s_per_step": (t_long - t_one) / ((steps[m] - 1) * lanes), "lanes": lanes,
                  "steps": steps[m], "one_step_s": t_one, "long_s": t_long, "repeats": repeats,
                  "spread": [min(per_step), max(per_step)]}
    return res


# --- trajectories ---------------------------------------------------------------------------------

def trajectories(binary, table, out, quick):
    lanes = 16384 if quick else 65536
    target, repeats = (0.15, 1) if quick else (0.7, 5)
    res = {}
    for scene, spec_path in SPECS.items():
        spec = spec_of(spec_path)
        t_end = float(spec["integrator"]["t_end"])
        ref = None
        if scene == "double_well":
            refs = {}
            for h in (REF_H_DW, REF_H_DW / 2):
                path = out / f"wp_double_well_reference_h{h:g}.h5"
                run(binary, spec_path, path, [method_set("contact_splitting6"),
                                              ("grid.h.values", toml_list([h]))])
                refs[h] = load(path)
            ref = refs[REF_H_DW]
            ref_err = float(error_double_well(refs[REF_H_DW / 2], ref)[0][0])
            print(f"\ndouble-well reference: contact_splitting6 at h = {REF_H_DW:g}; its estimated "
                  f"own error (against h = {REF_H_DW / 2:g}) = {ref_err:.2e}")
        r = {"t_end": t_end, "methods": {}}
        if ref is not None:
            r["reference"] = {"method": "contact_splitting6", "h": REF_H_DW, "own_error": ref_err}
        timing = time_per_step(binary, scene, table, out, lanes, target, repeats, quick)
        for m in table:
            path = out / f"wp_{scene}_{m}.h5"
            run(binary, spec_path, path, [method_set(m)])
            ds = load(path)
            h = ds.h.values
            err, herr = error_oscillator(ds, spec) if ref is None else error_double_well(ds, ref)
            order, npts = fit_order(h, err, FIT_LO[scene])
            r["methods"][m] = {"h": h.tolist(), "error": err.tolist(), "H_error": herr.tolist(),
                               "order_fit": order, "fit_points": npts, "fit_range": [FIT_LO[scene], FIT_HI],
                               "s_per_step": timing[m]["s_per_step"], "timing": timing[m]}
        error = (lambda ds: error_oscillator(ds, spec)) if ref is None else (
            lambda ds: error_double_well(ds, ref))
        r["adaptive"] = adaptive.trajectories(binary, scene, spec_path, error, out, quick, load)
        res[scene] = r
    return res


def long_time_H(binary, methods, out):
    """Relative H error on the oscillator at gamma = 0.01 over t = 10^4."""
    hs = [0.1, 0.05]
    res = {"gamma": 0.01, "t_end": 1e4, "h": hs, "methods": {}}
    spec = spec_of(SPECS["damped_oscillator"])
    spec["scene"]["gamma"] = 0.01
    H = exact_oscillator(spec, 0.0)[4]
    for m in methods:
        path = out / f"long_H_{m}.h5"
        run(binary, SPECS["damped_oscillator"], path,
            [method_set(m), ("grid.h.values", toml_list(hs)), ("integrator.t_end", "10000.0"),
             ("scene.gamma", "0.01")])
        ds = load(path)
        e = abs(ds.final_H.values - H) / abs(H)
        e[ds.status.values != 0] = np.nan
        res["methods"][m] = e.tolist()
    return res


def print_trajectories(res, table):
    for scene, r in res.items():
        ms = r["methods"]
        h = np.array(next(iter(ms.values()))["h"])
        print(f"\n{scene}: error of the final state at t = {r['t_end']:g} against "
              + ("the exact solution" if scene == "damped_oscillator" else
                 f"contact_splitting6 at h = {r['reference']['h']:g} (own error "
                 f"{r['reference']['own_error']:.1e})") + " (NaN: a lane failed)")
        print(f"{'h':>8s}" + "".join(f"{m:>20s}" for m in ms))
        for i, hi in enumerate(h):
            print(f"{hi:8g}" + "".join(f"{ms[m]['error'][i]:20.2e}" for m in ms))
        print(f"{'method':20s}{'order':>6s}{'observed':>10s}{'points':>7s}{'ns/step':>9s}"
              f"{'(range of repeats)':>20s}{'evals/step':>11s}{'ns/eval':>9s}")
        for m, d in ms.items():
            o, ev = table[m]
            lo, hi = d["timing"]["spread"]
            print(f"{m:20s}{o:6d}{d['order_fit']:10.2f}{d['fit_points']:7d}{d['s_per_step'] * 1e9:9.3f}"
                  f"{f'({lo * 1e9:.2f} - {hi * 1e9:.2f})':>20s}{ev:11d}{d['s_per_step'] * 1e9 / ev:9.3f}")
            print(f"order {scene} {m}: observed {d['order_fit']:.3f} (nominal {o})")
        print(f"relative H error at t = {r['t_end']:g}:")
        print(f"{'h':>8s}" + "".join(f"{m:>20s}" for m in ms))
        for i, hi in enumerate(h):
            print(f"{hi:8g}" + "".join(f"{ms[m]['H_error'][i]:20.2e}" for m in ms))
        # Cheapest method (time per trajectory) reaching each tolerance.
        print(f"cheapest method per tolerance ({scene}, time per trajectory at the h, interpolated, "
              "where the error reaches it):")
        for tol in (1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10):
            best = cheapest(r, tol)
            print(f"  error <= {tol:.0e}: " + ", ".join(
                f"{m} {c * 1e6:.2f} us (h = {hh:.3g})" for m, c, hh in best[:3]))
        if "adaptive" in r:
            adaptive.print_trajectories(scene, r["adaptive"])


def cheapest(r, tol):
    """[(method, time per trajectory s, h)] sorted by time: per method, the step size at which its
    error reaches tol, interpolated log-log between the two step sizes of the spec around it
    (h and time are exact where a measured error lands on tol). Only the error curve from the
    largest h down to the first h that meets tol is used; a method whose largest h already meets
    tol is charged that h."""
    out = []
    for m, d in r["methods"].items():
        h = np.array(d["h"])
        e = np.array([np.nan if x is None else x for x in d["error"]], dtype=float)
        ok = np.isfinite(e) & (e <= tol)
        if not ok.any():
            continue
        i = int(np.argmax(ok))  # h is in decreasing order
        hh = h[i]
        if i > 0 and np.isfinite(e[i - 1]) and e[i - 1] > tol:
            w = np.log(tol / e[i]) / np.log(e[i - 1] / e[i])
            hh = float(np.exp(np.log(h[i]) + w * np.log(h[i - 1] / h[i])))
        out.append((m, r["t_end"] / hh * d["s_per_step"], float(hh)))
    return sorted(out, key=lambda x: x[1])


def chart_trajectories(res, table, out):
    paths = []
    for scene, r in res.items():
        fig, axes = plt.subplots(1, 3, figsize=(16, 5.2))
        t_end = r["t_end"]
        for m, d in r["methods"].items():
            color, marker = METHOD_STYLE.get(m, ("k", "x"))
            h, e = np.array(d["h"]), np.array(d["error"])
            steps = t_end / h
            kw = dict(color=color, marker=marker, ms=4, lw=1.2)
            label = f"{m} (order {table[m][0]}, observed {d['order_fit']:.2f})"
            axes[0].loglog(h, e, label=label, **kw)
            axes[1].loglog(steps * d["s_per_step"], e, label=f"{m}: {d['s_per_step'] * 1e9:.2f} ns/step", **kw)
            axes[2].loglog(steps * table[m][1], e, label=f"{m}: {table[m][1]} eval/step", **kw)
        if "adaptive" in r:
            adaptive.chart_trajectories(axes, r["adaptive"])
        if "reference" in r:
            for ax in axes:
                ax.axhline(r["reference"]["own_error"], color="k", lw=0.8, ls="--",
                           label=f"reference's own error ({r['reference']['own_error']:.1e})")
        axes[0].set_xlabel("step size h")
        axes[1].set_xlabel("time per trajectory [s]  (t_end / h × measured time per trajectory-step, 1 core)")
        axes[2].set_xlabel("force evaluations per trajectory")
        for ax in axes:
            ax.set_ylabel("error of the final state")
            ax.grid(True, which="major", lw=0.4, alpha=0.5)
            ax.legend(fontsize="x-small", loc="lower left" if ax is not axes[0] else "lower right")
        what = ("exact solution" if scene == "damped_oscillator"
                else f"contact_splitting6 at h = {r['reference']['h']:g}")
        fig.suptitle(f"Work-precision, {scene.replace('_', ' ')}: error at t = {t_end:g} against the "
                     f"{what}")
        path = out / f"workprecision_{scene}.png"
        save(fig, path)
        paths.append(path)
    return paths


# --- basin maps -----------------------------------------------------------------------------------

# The basin maps whose accuracy is charted: the double well (its exact trap) and the magnetic
# pendulum (three attractors, fractal boundaries; K in the spec, its energy trap found at set-up).
BASIN_CASES = {
    "double_well": dict(spec=BASIN_SPEC, axes=("q_0", "p_0"), t_end=100.0,
                        n=(64, 512), h_ref=(0.005, 0.0025),
                        hs=([0.2, 0.1, 0.05], [0.25, 0.2, 0.125, 0.1, 0.05, 0.025, 0.0125, 0.01]),
                        title="the damped double well", chart="basin_accuracy.png"),
    "magnetic_pendulum": dict(spec=SWEEPS / "basins_magnetic_pendulum.toml", axes=("q1_0", "q2_0"),
                              t_end=200.0, n=(24, 128), h_ref=(0.01, 0.0025),
                              hs=([0.1, 0.05], [0.1, 0.05, 0.04, 0.025, 0.02, 0.01]),
                              title="the magnetic pendulum",
                              chart="basin_accuracy_magnetic_pendulum.png"),
}


def basins(binary, methods, out, quick, case="double_well"):
    c = BASIN_CASES[case]
    spec = c["spec"]
    n, h_ref, hs = (c[k][0 if quick else 1] for k in ("n", "h_ref", "hs"))
    repeats = 1 if quick else 5
    grid = [(f"grid.{c['axes'][0]}.n", n), (f"grid.{c['axes'][1]}.n", n)]
    labels = {}
    for h in (h_ref, h_ref / 2):
        path = out / f"basin_{case}_reference_h{h:g}.h5"
        run(binary, spec, path, grid + [method_set("contact_splitting6"), ("integrator.h", repr(h))])
        labels[h] = load(path).basin.values
    ref = labels[h_ref]
    ref_diff = float((labels[h_ref] != labels[h_ref / 2]).mean())
    # One step: the launch (wall) and the program's set-up and write (its own time).
    launch, setup = median_times(binary, spec, out / f"basin_{case}_launch.h5",
                                 grid + [("integrator.h", "0.25"), ("integrator.t_end", "0.25")], repeats)
    res = {"case": case, "n": n, "t_end": c["t_end"], "h_ref": h_ref, "ref_diff": ref_diff,
           "one_step_wall_s": launch, "one_step_s": setup, "repeats": repeats, "methods": {}}
    # Rounds over every (method, h) in turn, so a burst of load from other work on the machine
    # does not land on one method only; medians over the rounds.
    # dop853 over rtol (work_precision_adaptive.py) in the same rounds.
    runs = {(m, h): (f"{m}_h{h:g}", [method_set(m), ("integrator.h", repr(h))])
            for m in methods for h in hs}
    runs.update({(adaptive.METHOD, r): (f"{adaptive.METHOD}_rtol{r:g}", adaptive.settings(r))
                 for r in adaptive.BASIN_RTOLS[0 if quick else 1]})
    times = {k: [] for k in runs}
    for _ in range(repeats):
        for k, (name, sets) in runs.items():
            times[k].append(run_timed(binary, spec, out / f"basin_{case}_{name}.h5", grid + sets))
    for m in methods:
        rows = []
        for h in hs:
            ds = load(out / f"basin_{case}_{m}_h{h:g}.h5")
            t = np.array(times[m, h])
            rows.append({"h": h, "wall_s": float(np.median(t[:, 0])), "time_s": float(np.median(t[:, 1])),
                         "time_range_s": [float(t[:, 1].min()), float(t[:, 1].max())],
                         "differ": float((ds.basin.values != ref).mean()),
                         "failed": float((ds.status.values != 0).mean())})
        res["methods"][m] = rows
    res["adaptive"] = []
    for (m, r), (name, _) in runs.items():
        if m != adaptive.METHOD:
            continue
        ds, t = load(out / f"basin_{case}_{name}.h5"), np.array(times[m, r])
        res["adaptive"].append({"rtol": r, "time_s": float(np.median(t[:, 1])),
                                "time_range_s": [float(t[:, 1].min()), float(t[:, 1].max())],
                                "differ": float((ds.basin.values != ref).mean()),
                                "failed": float((ds.status.values != 0).mean())})
    print(f"\n{c['title']}: basin map {n} x {n} (t_end = {c['t_end']:g}, early stop): fraction of cells whose basin differs "
          f"from contact_splitting6 at h = {h_ref:g} (which itself differs from h = {h_ref / 2:g} "
          f"in {ref_diff:.2e} = {round(ref_diff * n * n)} cells). Time: the program's own time "
          f"(set-up, integrate, write; 1 thread, median of {repeats}); a one-step map takes "
          f"{setup:.3f} s of it, and the command's wall time adds the process launch "
          f"({launch - setup:.2f} s)")
    print("per method: differing fraction (cells), time [s]")
    print(f"{'h':>8s}" + "".join(f"{m:>26s}" for m in methods))
    for i, h in enumerate(hs):
        cells = [res["methods"][m][i] for m in methods]
        print(f"{h:8g}" + "".join(f"{c['differ']:>11.2e}{'(%d)' % round(c['differ'] * n * n):>8s}"
                                  f"{c['time_s']:>7.3f}" for c in cells))
    for r in res["adaptive"]:
        print(f"{adaptive.METHOD} rtol {r['rtol']:g}: {r['differ']:.2e} "
              f"({round(r['differ'] * n * n)} cells), {r['time_s']:.3f} s")
    for m in methods:
        bad = [r["h"] for r in res["methods"][m] if r["failed"] > 0]
        if bad:
            print(f"  {m}: failed lanes (diverged / breakdown) at h = {bad}")
    return res


def chart_basins(res, out):
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2))
    floor = 0.5 / res["n"] ** 2
    for m, rows in res["methods"].items():
        color, marker = METHOD_STYLE.get(m, ("k", "x"))
        f = np.maximum([r["differ"] for r in rows], floor)
        axes[0].loglog([r["time_s"] for r in rows], f, color=color, marker=marker, ms=4, lw=1.2, label=m)
        axes[1].loglog([r["h"] for r in rows], f, color=color, marker=marker, ms=4, lw=1.2, label=m)
    if res.get("adaptive"):
        adaptive.chart_basins(axes[0], res["adaptive"], floor)
    for ax in axes:
        ax.axhline(floor, color="0.5", lw=0.8, ls=":", label="no cell differs (drawn at half a cell)")
        if res["ref_diff"] > 0:
            ax.axhline(res["ref_diff"], color="k", lw=0.8, ls="--", label="reference against h / 2")
        ax.set_ylabel("fraction of cells in another basin than the reference")
        ax.grid(True, which="major", lw=0.4, alpha=0.5)
        ax.legend(fontsize="small")
    axes[0].axvline(res["one_step_s"], color="0.5", lw=0.8, ls="-.")
    axes[0].set_xlabel("time to compute the map [s]: the program's own time, 1 thread "
                       "(dash-dot: a one-step map)")
    axes[1].set_xlabel("step size h")
    c = BASIN_CASES[res.get("case", "double_well")]
    fig.suptitle(f"Basin map of {c['title']}, {res['n']} × {res['n']} cells, t = {res['t_end']:g}: "
                 f"cells whose basin differs from contact_splitting6 at h = {res['h_ref']:g}")
    path = out / c["chart"]
    save(fig, path)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", type=Path, default=ROOT / "build" / "contactsweep", help="contactsweep executable")
    ap.add_argument("--out", type=Path, required=True, help="directory for the .h5 files, JSON and PNGs")
    ap.add_argument("--quick", action="store_true", help="short timings, small map (seconds), for tests")
    ap.add_argument("--replot", action="store_true", help="only redraw the charts from DIR/work_precision.json")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    if args.replot:
        res = json.loads((args.out / "work_precision.json").read_text())
        table = {m: (d["order"], d["evals_per_step"]) for m, d in res["methods"].items()}
        chart_trajectories(res["trajectories"], table, args.out)
        chart_basins(res["basins"], args.out)
        if "basins_magnetic_pendulum" in res:
            chart_basins(res["basins_magnetic_pendulum"], args.out)
        return 0
    start = time.perf_counter()
    table = methods_table(args.bin)
    methods = list(table)
    res = {"quick": args.quick, "methods": {m: {"order": o, "evals_per_step": e} for m, (o, e) in table.items()}}
    res["trajectories"] = trajectories(args.bin, table, args.out, args.quick)
    print_trajectories(res["trajectories"], table)
    res["long_time_H"] = lt = long_time_H(args.bin, methods, args.out)
    print(f"\nrelative H error on the oscillator, gamma = {lt['gamma']:g}, t = {lt['t_end']:g}:")
    print(f"{'method':20s}" + "".join(f"{f'h = {h:g}':>12s}" for h in lt["h"]))
    for m, e in lt["methods"].items():
        print(f"{m:20s}" + "".join(f"{x:12.2e}" for x in e))
    chart_trajectories(res["trajectories"], table, args.out)
    res["basins"] = basins(args.bin, methods, args.out, args.quick)
    chart_basins(res["basins"], args.out)
    res["basins_magnetic_pendulum"] = basins(args.bin, methods, args.out, args.quick,
                                             "magnetic_pendulum")
    chart_basins(res["basins_magnetic_pendulum"], args.out)
    res["runtime_s"] = time.perf_counter() - start
    write_output(args.out / "work_precision.json",
                 lambda f: json.dump(res, f, indent=1, default=float, allow_nan=True), text=True)
    print(f"\nwork_precision: {res['runtime_s']:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
