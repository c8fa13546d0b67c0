#!/usr/bin/python3
"""Figures 1-3 of the paper from contactsweep output.

  plot_paper_figures.py --in out --out out/figures

reads paper_fig1a.h5, paper_fig1b.h5 (scenes A, B), paper_fig2.h5 (double well, grid q_0 = -2, 2)
and paper_fig3.h5 (coupled oscillators, grid g = 0, 0.8), all with the `trajectory` measure, and
writes fig1.png, fig2.png, fig3.png. Titles carry the parameters stored in each file.
"""
import argparse
import sys
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from safe_output import save_figure  # noqa: E402  (lives next to this script)

GREEK = {"gamma": "γ", "omega": "ω", "omega1_sq": "ω₁²", "omega2_sq": "ω₂²", "g": "g", "a": "a"}


def attr(ds, name, default=""):
    """A root attribute as a plain Python value (h5py may hand back bytes or 1-element arrays)."""
    v = ds.attrs.get(name, default)
    if isinstance(v, np.ndarray) and v.size == 1:
        v = v.item()
    return v.decode() if isinstance(v, bytes) else v


def scene_params(ds):
    """The [scene] table of the stored spec (after --set), without its name."""
    spec = tomllib.loads(attr(ds, "spec")) if attr(ds, "spec") else {}
    return {k: v for k, v in spec.get("scene", {}).items() if k != "name"}


def params_text(ds, skip=()):
    return ", ".join(f"{GREEK.get(k, k)} = {v:g}" for k, v in scene_params(ds).items() if k not in skip)


def run_text(ds):
    return f"{attr(ds, 'method')}, h = {float(attr(ds, 'h', np.nan)):g}"


def fig1(a, b, out):
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(a.t, a.traj_q, label=f"(A) K = (p² + ω²q²)/2 − γz;  {params_text(a)}")
    ax.plot(b.t, b.traj_q, label=f"(B) K = (p² + ω²q²)/2 − γz²;  {params_text(b)}")
    ax.set(xlabel="t", ylabel="q(t)",
           title=f"Fig. 1: damping linear vs quadratic in z ({run_text(a)})")
    ax.axhline(0, color="0.7", lw=0.5)
    ax.legend(loc="upper right")
    save(fig, out / "fig1.png")


def fig2(ds, out):
    q = ds.traj_q
    fig, ax = plt.subplots(figsize=(8, 4.5))
    colors = {}
    for q0 in ds.q_0.values:
        line, = ax.plot(ds.t, q.sel(q_0=q0), label=f"q(t) from q₀ = {q0:+g}")
        colors[q0] = line.get_color()
    # The potential is even in q, so the run from -q0 must be the mirror image of the run from
    # q0: -q(t; q0) is drawn dashed and should lie on the other solid curve.
    for q0 in ds.q_0.values:
        ax.plot(ds.t, -q.sel(q_0=q0), ls="--", color=colors[q0], lw=1.2,
                label=f"−q(t) from q₀ = {q0:+g} (mirror)")
    if ds.q_0.size == 2:
        asym = float(np.nanmax(np.abs(q.isel(q_0=0) + q.isel(q_0=1))))
        print(f"fig2: max |q(t; {ds.q_0.values[0]:g}) + q(t; {ds.q_0.values[1]:g})| = {asym:.3g}")
    a = scene_params(ds).get("a", 1.0)
    for w in (-a, a):
        ax.axhline(w, color="0.6", lw=0.6, ls=":")
    ax.set(xlabel="t", ylabel="q(t)",
           title=f"Fig. 2: double well K = p²/2 + (q² − a²)²/2 − γz\n{params_text(ds)}; {run_text(ds)}")
    ax.legend(loc="upper right", fontsize="small")
    save(fig, out / "fig2.png")


def fig3(ds, out):
    gs = ds.g.values
    fig, axes = plt.subplots(1, len(gs), figsize=(6 * len(gs), 4.5), sharey=True, squeeze=False)
    for ax, g in zip(axes[0], gs):
        for var, label in (("traj_q1", "q₁"), ("traj_q2", "q₂")):
            ax.plot(ds.t, ds[var].sel(g=g), label=label, lw=1)
        ax.set(xlabel="t", title=f"g = {g:g}" + (" (independent)" if g == 0 else ""))
        ax.legend(loc="upper right")
    axes[0][0].set_ylabel("q₁(t), q₂(t)")
    fig.suptitle(f"Fig. 3: coupled oscillators K = Σ(pᵢ² + ωᵢ²qᵢ²)/2 + g q₁²q₂² − γz\n"
                 f"{params_text(ds, skip=('g',))}; {run_text(ds)}")
    save(fig, out / "fig3.png")


def save(fig, path):
    fig.tight_layout()
    save_figure(fig, path, dpi=120)
    plt.close(fig)
    print(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--in", dest="indir", type=Path, required=True, help="directory with the .h5 files")
    ap.add_argument("--out", dest="outdir", type=Path, required=True, help="directory for the PNGs")
    args = ap.parse_args()
    args.outdir.mkdir(parents=True, exist_ok=True)

    def load(name):
        path = args.indir / f"{name}.h5"
        return xr.open_dataset(path, engine="h5netcdf").load() if path.exists() else None

    figures = [(fig1, ["paper_fig1a", "paper_fig1b"]), (fig2, ["paper_fig2"]), (fig3, ["paper_fig3"])]
    missing = []
    for make, names in figures:
        data = [load(n) for n in names]
        if any(d is None for d in data):
            missing += [f"{n}.h5" for n, d in zip(names, data) if d is None]
            continue
        make(*data, args.outdir)
    if missing:
        print(f"plot_paper_figures: missing in {args.indir}: {', '.join(missing)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
