#!/usr/bin/python3
"""Basin maps of any system (measures.basin on any scene; docs/basins.md).

  plot_basins.py OUT_DIR FILE.h5 [FILE.h5 ...]

Each file becomes OUT_DIR/<file stem>.png: the basin map over its last two grid axes, every
attractor of the table marked where it lies on the plane (when the plane is a plane of its
variables), fractions in the legend, S_b, S_bb and the uncertainty exponent in the title. A file
whose first axis is a parameter (a continuation) gets the maps at its first and last values and
the chart of the fractions and of S_b, S_bb against that parameter. The numbers are printed too.
"""
import math
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

from plot_maps import centers_extent  # noqa: E402  (lives next to this script)
from safe_output import save_figure  # noqa: E402

UNDECIDED = "0.15"


def text(f, name):
    value = f.attrs[name]
    return value.decode() if isinstance(value, bytes) else str(value)


def axis_names(f):
    return [d[0].name.lstrip("/") for d in f["basin"].dims]


def colours(labels):
    """One colour per label (black for 0), in the order of `labels`."""
    palette = plt.get_cmap("tab10")
    return {0: UNDECIDED} | {int(l): palette(k % 10) for k, l in enumerate(labels)}


def draw_map(ax, f, labels2d, xname, yname, colour, value=None):
    """The map, each attractor marked where it is (at the continuation's `value`-th value if
    given: branch_<var>, NaN where it is not found there)."""
    table = [int(l) for l in f["attractor_label"][...]]
    codes = {l: k for k, l in enumerate([0] + table)}
    index = np.vectorize(lambda l: codes.get(int(l), 0))(labels2d)
    cmap = ListedColormap([colour[l] for l in [0] + table])
    ax.imshow(index.T, origin="lower", aspect="auto", interpolation="nearest", cmap=cmap,
              vmin=-0.5, vmax=len(table) + 0.5,
              extent=centers_extent(f[xname][...]) + centers_extent(f[yname][...]))
    xvar, yvar = xname.removesuffix("_0"), yname.removesuffix("_0")
    where = ([f[f"branch_{v}"][value] for v in (xvar, yvar)]
             if value is not None and f"branch_{xvar}" in f and f"branch_{yvar}" in f
             else [f[f"attractor_{v}"][...] for v in (xvar, yvar)]
             if f"attractor_{xvar}" in f and f"attractor_{yvar}" in f else None)
    if where is not None:
        for k, l in enumerate(table):
            ax.plot(where[0][k], where[1][k], "o", ms=7, mfc=colour[l], mec="white", mew=1.5)
    ax.set(xlabel=xname, ylabel=yname)


def legend(ax, f, colour, fractions=None):
    fractions = f["attractor_fraction"][...] if fractions is None else fractions
    periods = f["attractor_period"][...]
    # The attractors' coordinates: attractor_<variable>, one value per attractor (not the
    # description's kind, exponent, period in time or points, docs/output.md).
    described = ("label", "period", "fraction", "cells", "kind", "lyapunov", "time_period", "points")
    variables = [k.removeprefix("attractor_") for k in f
                 if k.startswith("attractor_") and k.removeprefix("attractor_") not in described
                 and f[k].ndim == 1]
    for k, l in enumerate(f["attractor_label"][...]):
        where = ", ".join(f"{v} = {f['attractor_' + v][k]:.3g}" for v in variables)
        kind = "fixed point" if periods[k] == 1 else f"{periods[k]}-cycle"
        ax.plot([], [], "s", color=colour[int(l)], label=f"{l}: {kind} ({where}) {fractions[k]:.3f}")
    ax.plot([], [], "s", color=UNDECIDED, label=f"0: undecided {f.attrs['undecided_fraction']:.3f}")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)


def statistics_line(f):
    return (f"S_b = {f.attrs['basin_entropy']:.3f}, S_bb = {f.attrs['boundary_basin_entropy']:.3f} "
            f"({'>' if f.attrs['boundary_basin_entropy'] > math.log(2) else '≤'} ln 2), "
            f"uncertainty exponent α = {f.attrs['uncertainty_exponent']:.2f}")


def single_map(f, path):
    xname, yname = axis_names(f)[-2:]
    colour = colours(f["attractor_label"][...])
    fig, ax = plt.subplots(figsize=(9.5, 5.2), layout="constrained")
    draw_map(ax, f, f["basin"][...], xname, yname, colour)
    legend(ax, f, colour)
    ax.set_title(statistics_line(f), fontsize=9)
    fig.suptitle(text(f, "title"), fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)


def continuation(f, path):
    names = axis_names(f)
    pname, xname, yname = names[0], names[-2], names[-1]
    values = f[pname][...]
    colour = colours(f["attractor_label"][...])
    fig = plt.figure(figsize=(13, 4.6), layout="constrained")
    grid = fig.add_gridspec(1, 3)
    for k, i in enumerate((0, len(values) - 1)):
        ax = fig.add_subplot(grid[0, k])
        draw_map(ax, f, f["basin"][i], xname, yname, colour, value=i)
        ax.set_title(f"{pname} = {values[i]:g}: S_b = {f['basin_entropy'][i]:.2f}, "
                     f"S_bb = {f['boundary_basin_entropy'][i]:.2f}", fontsize=9)
    cx = fig.add_subplot(grid[0, 2])
    fractions = f["basin_fraction"][...]
    for k, l in enumerate(f["attractor_label"][...]):
        cx.plot(values, fractions[:, k], "o-", color=colour[int(l)], label=f"fraction, basin {l}")
    cx.plot(values, f["basin_entropy"][...], "k--", label="S_b")
    cx.plot(values, f["boundary_basin_entropy"][...], "k:", label="S_bb")
    cx.axhline(math.log(2), color="0.6", lw=0.8)
    cx.text(values[-1], math.log(2), "ln 2", va="bottom", ha="right", fontsize=8, color="0.4")
    cx.set(xlabel=pname, ylabel="fraction / entropy", xscale="log",
           title="continuation over " + pname)
    cx.legend(fontsize=8)
    fig.suptitle(text(f, "title"), fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for name in sys.argv[2:]:
        with h5py.File(name, "r") as f:
            path = out / (Path(name).stem + ".png")
            if "basin_fraction" in f and "basin_entropy" in f:
                continuation(f, path)
            else:
                single_map(f, path)
            table = ", ".join(
                f"{l}: period {p}, fraction {x:.4f}" for l, p, x in
                zip(f["attractor_label"][...], f["attractor_period"][...], f["attractor_fraction"][...]))
            print(f"{path}: {table}; undecided {f.attrs['undecided_fraction']:.4f}; {statistics_line(f)}")


if __name__ == "__main__":
    main()
