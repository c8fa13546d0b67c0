#!/usr/bin/python3
"""Stability maps over the step size h, one panel per integrator.

  stability_maps.py --bin build/contactsweep --out out/stability [--quick]

Runs sweeps/stability_h_gamma.toml (damped oscillator, status over h x gamma) and
sweeps/stability_h_q0.toml (double well, status and basin over h x q0) once per method
(--set integrator.method=NAME), writing DIR/<spec>_<method>.h5, and draws
  DIR/stability_h_gamma.png   status over (h, gamma), the measured limit at gamma = 0.1 marked;
  DIR/stability_h_q0.png      status and basin over (h, q0); cells whose basin differs from a fine
                              reference (contact_splitting6 at h = 0.001 on the same q0 axis,
                              integrated to t_end without early stop) in black.
Prints, per method, the measured stability limit on the oscillator (first unstable h: a diverged
cell, or one that grew more than GROWTH-fold without reaching the divergence bound; and the largest
stable h below it) at gamma = 0, 0.1 and the largest gamma of the grid, next to the linear theory
(THEORY_LIMITS), and, on
the double well, the first h with a wrong well or a blow-up, over the whole q0 axis and from q0 = 2.
--quick: coarser gamma and q0 axes, every third h of the double-well map, a reference at h = 0.002
(seconds; for tests). The h axis of the oscillator map is kept whole: it sets the resolution of the
limits.
"""
import argparse
import os
import re
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import ListedColormap, to_rgb  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from safe_output import save_figure  # noqa: E402  (lives next to this script)

ROOT = Path(__file__).resolve().parents[2]
SWEEPS = ROOT / "sweeps"

# Linear stability limits on the oscillator at omega = 1, gamma = 0.1, derived from the published
# schemes by tests/stability_theory.py (which checks these 4-decimal tables, ctest
# stability_theory); drawn next to the measured ones.
THEORY_LIMIT_A = {"hybrid_leapfrog": 2.0, "symmetric_leapfrog": 2.0, "contact_splitting2": 2.0,
                  "contact_splitting4": 1.5706, "contact_splitting6": 2.8118, "rk4": 2.9098}
# The same first limit at the ends of the gamma axis (tests/stability_theory.py as well). Beyond it:
# contact_splitting4 at gamma = 0.5 is stable again on [3.1350, 3.1637]; contact_splitting6 at
# gamma = 0 is unstable only on [2.2691, 2.3278] below 2.8173, and stable again on [3.1698, 3.2332].
THEORY_LIMITS = {
    0.0: {"hybrid_leapfrog": 2.0, "symmetric_leapfrog": 2.0, "contact_splitting2": 2.0,
          "contact_splitting4": 1.5734, "contact_splitting6": 2.2691, "rk4": 2.8284},
    0.1: THEORY_LIMIT_A,
    0.5: {"hybrid_leapfrog": 2.0, "symmetric_leapfrog": 2.0, "contact_splitting2": 2.0,
          "contact_splitting4": 1.5035, "contact_splitting6": 2.6945, "rk4": 2.8967},
}
# One colour and marker per method in every chart of both scripts (work_precision.py imports these).
METHOD_STYLE = {"hybrid_leapfrog": ("tab:blue", "o"), "symmetric_leapfrog": ("tab:cyan", "v"),
                "contact_splitting2": ("tab:green", "s"), "contact_splitting4": ("tab:olive", "D"),
                "contact_splitting6": ("tab:purple", "^"), "rk4": ("tab:red", "P")}
DIVERGED, BREAKDOWN = to_rgb("#d62728"), to_rgb("#7b4173")
CELL = {"stable": to_rgb("#deebf7"), "diverged": DIVERGED, "breakdown": BREAKDOWN,
        "left": to_rgb("#9ecae1"), "right": to_rgb("#fdd0a2"), "undecided": to_rgb("#969696"),
        "wrong": (0.0, 0.0, 0.0), "grown": to_rgb("#f4a6a6")}
C_KEYS = ("left", "right", "undecided", "wrong", "diverged", "breakdown")  # double-well cells
GROWTH = 10.0  # |q(t_end)| > GROWTH |q0| without status 1: unstable, but slower than the bound


# --- running contactsweep (also used by work_precision.py) ----------------------------------------

def methods_table(binary):
    """{name: (order, force evaluations per step)} from `contactsweep methods`, in its order: the
    fixed-step methods, whose stability and accuracy these charts measure over h. An adaptive
    method ("step size: adaptive per lane") has no h to sweep; it is left out."""
    text = subprocess.run([str(binary), "methods"], check=True, capture_output=True, text=True).stdout
    table, name, fixed = {}, None, set()
    for line in text.splitlines():
        if line and not line[0].isspace():
            name = line.strip()
        m = re.match(r"\s+order (\d+), (\d+) force evaluation", line)
        if m and name:
            table[name] = (int(m[1]), int(m[2]))
        elif name and re.match(r"\s+step size: fixed\b", line):
            fixed.add(name)
    table = {k: v for k, v in table.items() if k in fixed}
    if not table:
        sys.exit(f"cannot read the methods from `{binary} methods`:\n{text}")
    return table


def run(binary, spec, out, sets=(), threads=1):
    """contactsweep run SPEC -o OUT --force --quiet --set ...; returns the wall time in seconds.
    sets: (key, value) pairs, values written as TOML (strings need their quotes)."""
    cmd = [str(binary), "run", str(spec), "-o", str(out), "--force", "--quiet"]
    for key, value in sets:
        cmd += ["--set", f"{key}={value}"]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"failed (exit {proc.returncode}): {' '.join(cmd)}\n{proc.stderr}")
    return wall


def method_set(name):
    return ("integrator.method", f'"{name}"')


def toml_list(values):
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def load(path):
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def edges(x):
    """Cell edges around (possibly uneven) grid values, for pcolormesh."""
    x = np.asarray(x, dtype=float)
    if len(x) == 1:
        return np.array([x[0] - 0.5, x[0] + 0.5])
    mid = (x[1:] + x[:-1]) / 2
    return np.concatenate([[x[0] - (mid[0] - x[0])], mid, [x[-1] + (x[-1] - mid[-1])]])


def save(fig, path, legend_rows=0):
    """legend_rows: rows of a figure legend at the bottom to leave room for."""
    fig.tight_layout(rect=(0, 0.025 + 0.03 * legend_rows, 1, 1))
    save_figure(fig, path, dpi=120)
    plt.close(fig)
    print(f"wrote {path}")


def panel_grid(n):
    cols = 3 if n > 4 else n
    rows = -(-n // cols)
    return rows, cols


# --- the oscillator: status over (h, gamma) -------------------------------------------------------

def limit_at(h, status_row):
    """(first h with a failed cell, largest stable h below it, stable windows beyond it)."""
    bad = status_row != 0
    if not bad.any():
        return np.inf, h[-1], []
    i = int(np.argmax(bad))
    windows, j = [], i
    while j < len(h):  # stable again further up (contact_splitting6 has such an island)
        if not bad[j]:
            k = j
            while k + 1 < len(h) and not bad[k + 1]:
                k += 1
            windows.append((h[j], h[k]))
            j = k + 1
        else:
            j += 1
    return h[i], (h[i - 1] if i > 0 else np.nan), windows


def oscillator(binary, methods, out, quick):
    spec = SWEEPS / "stability_h_gamma.toml"
    sets = [("grid.gamma.n", 11)] if quick else []  # n = 11 keeps gamma = 0.1 on the grid
    q0 = abs(tomllib.loads(spec.read_text())["initial"]["q"])
    results, walls = {}, {}
    for m in methods:
        path = out / f"stability_h_gamma_{m}.h5"
        walls[m] = run(binary, spec, path, sets + [method_set(m)])
        results[m] = load(path)
    print("oscillator map run times (s, 1 thread): "
          + ", ".join(f"{m} {w:.2f}" for m, w in walls.items()))

    # Per cell: 0 stable, 1 diverged, 2 breakdown (the status), 3 grew more than GROWTH-fold but
    # stayed below the divergence bound: unstable, but too slowly to be flagged by t_end.
    def category(ds):
        s = ds.status.transpose("gamma", "h").values.astype(int)
        grew = np.abs(ds.final_q.transpose("gamma", "h").values) > GROWTH * q0
        return np.where((s == 0) & grew, 3, s)

    g_all = results[methods[0]].gamma.values
    i01 = int(np.argmin(abs(g_all - 0.1)))
    g01 = float(g_all[i01])
    g_show = sorted({float(g_all[0]), g01, float(g_all[-1])})

    def theory_at(m, g):
        known = [k for k in THEORY_LIMITS if abs(k - g) < 1e-9]
        return THEORY_LIMITS[known[0]].get(m, np.nan) if known else np.nan

    print("\nstability limits on the damped oscillator (omega = 1): first unstable h (diverged, or grew "
          f"> {GROWTH:g}x) [largest stable h below it] (linear theory)")
    print(f"{'method':20s}" + "".join(f"{f'gamma = {g:g}':>32s}" for g in g_show))
    limits = {}
    for m, ds in results.items():
        h = ds.h.values
        cat = category(ds)
        cells = []
        for g in g_show:
            first, below, _ = limit_at(h, cat[int(np.argmin(abs(g_all - g)))])
            cells.append(f"{first:.4f} [{below:.4f}] ({theory_at(m, g):.4f})")
        first, below, windows = limit_at(h, ds.status.isel(gamma=i01).values)
        grown = limit_at(h, cat[i01])
        limits[m] = (first, below, windows) + grown[:2]
        print(f"{m:20s}" + "".join(f"{c:>32s}" for c in cells))
    for m, (first, below, windows, g_first, g_below) in limits.items():
        # The line tests/test_stability_maps.py reads: keep its shape.
        print(f"limit A {m}: first diverged h = {first:.6f}, largest stable h below = {below:.6f}, "
              f"first grown h = {g_first:.6f}, largest decaying h below = {g_below:.6f} "
              f"(gamma = {g01:g})" + "".join(f"; stable again on [{a:.4f}, {b:.4f}]" for a, b in windows))

    rows, cols = panel_grid(len(methods))
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.6 * rows + 1.2), sharex=True,
                             sharey=True, squeeze=False)
    cmap = ListedColormap([CELL["stable"], CELL["diverged"], CELL["breakdown"], CELL["grown"]])
    for ax, (m, ds) in zip(axes.flat, results.items()):
        ax.pcolormesh(edges(ds.h), edges(ds.gamma), category(ds), cmap=cmap, vmin=-0.5, vmax=3.5,
                      rasterized=True)
        g_first, g_below = limits[m][3:]
        ax.axhline(g01, color="0.35", lw=0.6, ls=":")
        theory = THEORY_LIMIT_A.get(m)
        if theory is not None:
            ax.axvline(theory, color="k", lw=0.9, ls="--")
        ends = [(theory_at(m, g), g) for g in (g_all[0], g_all[-1]) if np.isfinite(theory_at(m, g))]
        if ends:
            ax.plot(*zip(*ends), ls="none", marker="x", ms=6, mew=1.2, color="k", clip_on=False)
        ax.plot([g_first], [g01], marker="o", ms=5, mfc="none", mec="k")
        ax.set_title(f"{m}\nat γ = {g01:g}: stable up to h = {g_below:.4f}"
                     + (f" (theory {theory:.4f})" if theory else ""), fontsize="medium")
    for ax in axes.flat[len(results):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("step size h")
    for ax in axes[:, 0]:
        ax.set_ylabel("damping γ")
    fig.suptitle(f"Damped oscillator (ω = 1) from q₀ = {q0:g}, p₀ = 0, integrated to t = "
                 f"{float(results[methods[0]].attrs['t_end']):g}: stable or not, per step size")
    fig.legend(handles=[Patch(color=CELL["stable"], label="stable (decays, or bounded at γ = 0)"),
                        Patch(color=CELL["grown"], label=f"unstable: grew > {GROWTH:g}×, not yet past 10⁶"),
                        Patch(color=CELL["diverged"], label="diverged (|q| or |p| > 10⁶)"),
                        Patch(color=CELL["breakdown"], label="integrator breakdown"),
                        plt.Line2D([], [], color="k", ls="--", label=f"linear-theory limit at γ = {g01:g}"),
                        plt.Line2D([], [], color="k", marker="x", ls="none",
                                   label=f"linear-theory limit at γ = {g_all[0]:g} and {g_all[-1]:g}"),
                        plt.Line2D([], [], color="k", marker="o", mfc="none", ls="none",
                                   label=f"first unstable h at γ = {g01:g} (dotted line)")],
               loc="lower center", ncol=3, fontsize="small", frameon=False)
    save(fig, out / "stability_h_gamma.png", legend_rows=2)
    return limits


# --- the double well: status and basin over (h, q0) ----------------------------------------------

def double_well(binary, methods, out, quick):
    spec = SWEEPS / "stability_h_q0.toml"
    sets = []
    if quick:  # q0 step 0.1 keeps q0 = 2 on the grid; every third h
        spec_h = load_spec_h(spec)
        sets = [("grid.q_0.n", 61), ("grid.h.values", toml_list(spec_h[::3]))]
    results, walls = {}, {}
    for m in methods:
        path = out / f"stability_h_q0_{m}.h5"
        walls[m] = run(binary, spec, path, sets + [method_set(m)])
        results[m] = load(path)
    print("\ndouble-well map run times (s, 1 thread): "
          + ", ".join(f"{m} {w:.2f}" for m, w in walls.items()))

    # The reference: the same q0 axis, 6th order at a small step, every lane to t_end (no early
    # stop, so it does not lean on the energy trap's margin); checked against half its step.
    h_ref = 0.002 if quick else 0.001
    refs = {}
    for h in (h_ref, h_ref / 2):
        path = out / f"stability_h_q0_reference_h{h:g}.h5"
        walls[h] = run(binary, spec, path, [x for x in sets if x[0] != "grid.h.values"]
            + [method_set("contact_splitting6"), ("grid.h.values", toml_list([h])),
               ("measures.basin.early_stop", "false")], threads=2)
        refs[h] = load(path).basin.isel(h=0).values
    ref = refs[h_ref]
    print(f"reference run times (s, 2 threads): h = {h_ref:g} {walls[h_ref]:.2f}, "
          f"h = {h_ref / 2:g} {walls[h_ref / 2]:.2f}")
    q0 = results[methods[0]].q_0.values
    n_check = int((refs[h_ref] != refs[h_ref / 2]).sum())
    print(f"\ndouble well reference: contact_splitting6, h = {h_ref:g}, to t = 100 without early stop; "
          f"{n_check} of {len(q0)} labels change at h = {h_ref / 2:g}; "
          f"undecided: {int((ref == 0).sum())} (q0 = 0 starts on the saddle)")

    i2 = int(np.argmin(abs(q0 - 2.0)))
    print(f"\ndouble well (a = 1, gamma = 0.1, p0 = 0, q0 in [{q0[0]:g}, {q0[-1]:g}]): first h with ...")
    print(f"{'method':20s}{'wrong well, any q0':>20s}{'blow-up, any q0':>18s}"
          f"{f'wrong well, q0 = {q0[i2]:g}':>22s}{f'blow-up, q0 = {q0[i2]:g}':>20s}")
    wrong_maps = {}
    for m, ds in results.items():
        h = ds.h.values
        b = ds.basin.transpose("h", "q_0").values.astype(int)
        s = ds.status.transpose("h", "q_0").values.astype(int)
        wrong = (s == 0) & (b != 0) & (ref[None, :] != 0) & (b != ref[None, :])
        wrong_maps[m] = wrong

        def first(mask):
            return f"{h[np.argmax(mask)]:.4f}" if mask.any() else "none"
        print(f"{m:20s}{first(wrong.any(axis=1)):>20s}{first((s != 0).any(axis=1)):>18s}"
              f"{first(wrong[:, i2]):>22s}{first(s[:, i2] != 0):>20s}")
        print(f"limit C {m}: first wrong-well h = {first(wrong.any(axis=1))}, "
              f"first blow-up h = {first((s != 0).any(axis=1))}")
        print(f"double well from q0 = {q0[i2]:g} {m}: first wrong-well h = {first(wrong[:, i2])}, "
              f"first blow-up h = {first(s[:, i2] != 0)}")

    rows, cols = panel_grid(len(methods))
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.6 * rows + 1.2), sharex=True,
                             sharey=True, squeeze=False)
    for ax, (m, ds) in zip(axes.flat, results.items()):
        b = ds.basin.transpose("q_0", "h").values.astype(int)
        s = ds.status.transpose("q_0", "h").values.astype(int)
        cat = np.full(b.shape, 2)  # the order of C_KEYS
        cat[b == -1] = 0
        cat[b == 1] = 1
        cat[wrong_maps[m].T] = 3
        cat[s == 1] = 4
        cat[s == 2] = 5
        ax.pcolormesh(edges(ds.h), edges(ds.q_0), cat, cmap=ListedColormap([CELL[k] for k in C_KEYS]),
                      vmin=-0.5, vmax=len(C_KEYS) - 0.5, rasterized=True)
        n_wrong = int(wrong_maps[m].sum())
        n_div = int((s != 0).sum())
        ax.set_title(f"{m}\n{n_wrong / s.size:.1%} wrong well, {n_div / s.size:.1%} diverged",
                     fontsize="medium")
    for ax in axes.flat[len(results):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("step size h")
    for ax in axes[:, 0]:
        ax.set_ylabel("initial position q₀  (p₀ = 0)")
    fig.suptitle("Damped double well (a = 1, γ = 0.1): which well each q₀ ends in, per step size; "
                 f"black: not the reference's well (contact_splitting6, h = {h_ref:g})")
    fig.legend(handles=[Patch(color=CELL["left"], label="left well, as the reference"),
                        Patch(color=CELL["right"], label="right well, as the reference"),
                        Patch(color=CELL["wrong"], label="the other well than the reference"),
                        Patch(color=CELL["undecided"], label="undecided by t = 100"),
                        Patch(color=CELL["diverged"], label="diverged"),
                        Patch(color=CELL["breakdown"], label="integrator breakdown")],
               loc="lower center", ncol=3, fontsize="small", frameon=False)
    save(fig, out / "stability_h_q0.png", legend_rows=2)


def load_spec_h(spec):
    with open(spec, "rb") as f:
        return tomllib.load(f)["grid"]["h"]["values"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", type=Path, default=ROOT / "build" / "contactsweep", help="contactsweep executable")
    ap.add_argument("--out", type=Path, required=True, help="directory for the .h5 files and PNGs")
    ap.add_argument("--quick", action="store_true", help="small grids (seconds), for tests")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    methods = list(methods_table(args.bin))
    start = time.perf_counter()
    oscillator(args.bin, methods, args.out, args.quick)
    double_well(args.bin, methods, args.out, args.quick)
    print(f"\nstability_maps: {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
