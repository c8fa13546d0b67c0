#!/usr/bin/python3
"""Showcases of attractors of every kind (docs/showcases.md).

  plot_showcases.py --in OUT_DIR --out FIG_DIR

Reads from OUT_DIR whichever of these runs exist (each spec in sweeps/), draws one PNG each into
FIG_DIR and prints the numbers the docs quote:
  basins_van_der_pol.h5                van der Pol's limit cycle: basin map, the cycle from
                                       attractor_points, attractor_time_period vs 6.6632868593
  basins_forced_duffing_autonomous.h5  the forced Duffing written autonomously beside its
  + basins_forced_duffing.h5           stroboscopic map: the fraction of cells that agree
  basins_forced_duffing_chaos.h5       a strange attractor beside a periodic orbit: basin map and
                                       the Poincare section from attractor_points
  basins_lorenz.h5                     the Lorenz attractor from attractor_points, lambda_1 vs 0.9056
  orbit_diagram_duffing.h5             the orbit diagram over F from stroboscopic samples
A missing file is skipped with a line saying so.
"""
import argparse
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

from plot_basins import axis_names, text  # noqa: E402  (both live next to this script)
from plot_maps import centers_extent  # noqa: E402
from safe_output import save_figure  # noqa: E402

VDP_PERIOD = 6.6632868593231301   # van der Pol at mu = 1 (period of the limit cycle)
VDP_AMPLITUDE = 2.0086198608      # its max |q1|
LORENZ_LAMBDA = 0.9056            # Lorenz, s = 10, r = 28, b = 8/3 (Sprott 2003)
KINDS = {0: "fixed point", 1: "periodic", 2: "quasi-periodic", 3: "chaotic", 4: "exit"}
UNDECIDED = "0.15"


def colours(f):
    palette = plt.get_cmap("tab10")
    return {0: UNDECIDED} | {int(l): palette(k % 10) for k, l in enumerate(f["attractor_label"][...])}


def basin_plane(ax, f, colour):
    """The basin map over its two grid axes, in the colours of `colour`."""
    xname, yname = axis_names(f)[-2:]
    table = [int(l) for l in f["attractor_label"][...]]
    codes = {l: k for k, l in enumerate([0] + table)}
    index = np.vectorize(lambda l: codes.get(int(l), 0))(f["basin"][...])
    ax.imshow(index.T, origin="lower", aspect="auto", interpolation="nearest",
              cmap=ListedColormap([colour[l] for l in [0] + table]), vmin=-0.5,
              vmax=len(table) + 0.5,
              extent=centers_extent(f[xname][...]) + centers_extent(f[yname][...]))
    ax.set(xlabel=xname, ylabel=yname)


def describe(f):
    """One line per attractor: label, kind, fraction, lambda_1, time period."""
    lines = []
    for k, l in enumerate(f["attractor_label"][...]):
        period = f["attractor_time_period"][k]
        lines.append(f"{l}: {KINDS[int(f['attractor_kind'][k])]}, fraction "
                     f"{f['attractor_fraction'][k]:.4f}, λ₁ = {f['attractor_lyapunov'][k]:.4f}"
                     + ("" if np.isnan(period) else f", T = {period:.8f}"))
    return lines


def legend(ax, f, colour):
    for line, l in zip(describe(f), f["attractor_label"][...]):
        ax.plot([], [], "s", color=colour[int(l)], label=line)
    ax.plot([], [], "s", color=UNDECIDED, label=f"0: undecided {f.attrs['undecided_fraction']:.4f}")


def van_der_pol(f, path):
    colour = colours(f)
    period, lam = f["attractor_time_period"][0], f["attractor_lyapunov"][0]
    points = f["attractor_points"][0]
    amplitude = np.max(np.abs(points[:, 0]))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    basin_plane(ax, f, colour)
    legend(ax, f, colour)
    ax.legend(loc="lower left", fontsize=8)
    ax.plot(points[:, 0], points[:, 1], ".", ms=2, color="k")
    ax.set_title("basin map (every cell: label 1), the cycle in black", fontsize=9)
    bx.plot(points[:, 0], points[:, 1], ".-", ms=3, lw=0.6, color=colour[1])
    bx.set(xlabel="q1", ylabel="q2", aspect="equal",
           title=f"attractor_points: T = {period:.10f} (exact {VDP_PERIOD:.10f}, "
                 f"error {period - VDP_PERIOD:+.1e})\nmax|q1| = {amplitude:.6f} (exact "
                 f"{VDP_AMPLITUDE:.6f}), λ₁ = {lam:+.1e}")
    bx.title.set_fontsize(9)
    fig.suptitle(text(f, "title"), fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return (f"period {period:.10f} vs {VDP_PERIOD:.10f} (error {period - VDP_PERIOD:+.2e}), "
            f"max|q1| {amplitude:.6f} vs {VDP_AMPLITUDE:.6f}, lambda_1 {lam:+.2e}; "
            f"undecided {f.attrs['undecided_fraction']:.4f}")


def well(f):
    """Each label's well: the sign of the mean q (q1) over its attractor_points."""
    points = f["attractor_points"][...]
    return {int(l): int(np.sign(points[k, :, 0].mean())) for k, l in enumerate(f["attractor_label"][...])}


def forced_autonomous(auto, strobe, path):
    """The autonomous map against the stroboscopic one on the points the two grids share."""
    ax_names, st_names = axis_names(auto), axis_names(strobe)
    xa, ya = auto[ax_names[0]][...], auto[ax_names[1]][...]
    xs, ys = strobe[st_names[0]][...], strobe[st_names[1]][...]
    ix = [int(np.argmin(np.abs(xs - x))) for x in xa]
    iy = [int(np.argmin(np.abs(ys - y))) for y in ya]
    if max(np.max(np.abs(xs[ix] - xa)), np.max(np.abs(ys[iy] - ya))) > 1e-9:
        return "the two grids share no points: nothing compared"
    wa, ws = well(auto), well(strobe)
    side_a = np.vectorize(lambda l: wa.get(int(l), 0))(auto["basin"][...])
    side_s = np.vectorize(lambda l: ws.get(int(l), 0))(strobe["basin"][...][np.ix_(ix, iy)])
    agree = side_a == side_s
    fraction = agree.mean()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), layout="constrained")
    colour = {-1: plt.get_cmap("tab10")(0), 1: plt.get_cmap("tab10")(1), 0: UNDECIDED}
    cmap = ListedColormap([colour[-1], colour[0], colour[1]])
    def short(f):
        return ", ".join(f"{KINDS[int(k)]} T = {t:.6f}" for k, t in
                         zip(f["attractor_kind"][...], f["attractor_time_period"][...]))
    for ax, side, f, names, title in ((axes[0], side_s, strobe, st_names,
                                       f"stroboscopic map (K with t, period = 5)\n{short(strobe)}"),
                                      (axes[1], side_a, auto, ax_names,
                                       f"autonomous (phase q2 an angle), by recurrences\n{short(auto)}")):
        ax.imshow(side.T, origin="lower", aspect="auto", interpolation="nearest", cmap=cmap,
                  vmin=-1.5, vmax=1.5, extent=centers_extent(xa) + centers_extent(ya))
        ax.set(xlabel=names[0], ylabel=names[1], title=title)
    axes[2].imshow(agree.T, origin="lower", aspect="auto", interpolation="nearest",
                   cmap=ListedColormap(["red", "0.9"]), vmin=-0.5, vmax=1.5,
                   extent=centers_extent(xa) + centers_extent(ya))
    axes[2].set(xlabel=ax_names[0], ylabel=ax_names[1],
                title=f"agree on {agree.sum()} of {agree.size} cells ({100 * fraction:.2f} %; red: differ)")
    for ax in axes[:2]:
        ax.plot([], [], "s", color=colour[-1], label="left-well orbit")
        ax.plot([], [], "s", color=colour[1], label="right-well orbit")
        ax.legend(loc="lower left", fontsize=8)
    for ax in axes:
        ax.title.set_fontsize(9)
    fig.suptitle("Forced double-well Duffing: its stroboscopic map and the same system written "
                 "autonomously, labelled by well", fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return (f"agree on {agree.sum()} of {agree.size} cells ({100 * fraction:.2f} %); autonomous: "
            + "; ".join(describe(auto)) + " | stroboscopic: " + "; ".join(describe(strobe)))


def forced_chaos(f, path):
    colour = colours(f)
    kinds = f["attractor_kind"][...]
    points = f["attractor_points"][...]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5), layout="constrained")
    basin_plane(ax, f, colour)
    legend(ax, f, colour)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"basin map: S_b = {f.attrs['basin_entropy']:.3f}, "
                 f"S_bb = {f.attrs['boundary_basin_entropy']:.3f}", fontsize=9)
    for k, l in enumerate(f["attractor_label"][...]):
        style = dict(ms=2, ls="none", marker=".") if kinds[k] == 3 else dict(ms=9, ls="none", marker="*")
        for axis in (ax, bx):
            axis.plot(points[k, :, 0], points[k, :, 1], color="k" if axis is ax else colour[int(l)],
                      **style, label=None if axis is ax else f"{l}: {KINDS[int(kinds[k])]}")
    bx.set(xlabel="q", ylabel="p", title="Poincaré section (t = 2πk/Ω) from attractor_points, "
                                         f"{points.shape[1]} periods")
    bx.title.set_fontsize(9)
    bx.legend(fontsize=8)
    fig.suptitle(text(f, "title"), fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return "; ".join(describe(f)) + f"; undecided {f.attrs['undecided_fraction']:.4f}"


def lorenz(f, path):
    points = f["attractor_points"][0]
    lam = f["attractor_lyapunov"][0]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    colour = colours(f)
    basin_plane(ax, f, colour)
    legend(ax, f, colour)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title("basin map (q3_0 = 25, p = 0): one attractor, every cell", fontsize=9)
    bx.plot(points[:, 0], points[:, 2], ".", ms=3, color=colour[1])
    bx.set(xlabel="q1 (x)", ylabel="q3 (z)",
           title=f"attractor_points ({len(points)} samples over t_end)\n"
                 f"{KINDS[int(f['attractor_kind'][0])]}, λ₁ = {lam:.4f} "
                 f"(literature {LORENZ_LAMBDA}: {100 * (lam / LORENZ_LAMBDA - 1):+.1f} %)")
    bx.title.set_fontsize(9)
    fig.suptitle(text(f, "title"), fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return (f"lambda_1 = {lam:.4f} vs {LORENZ_LAMBDA} ({lam - LORENZ_LAMBDA:+.4f}, "
            f"{100 * (lam / LORENZ_LAMBDA - 1):+.2f} %); " + "; ".join(describe(f)))


def orbit_diagram(f, path, kept=100):
    """q at the last `kept` stroboscopic samples of every lane against the first grid axis."""
    pname = [d[0].name.lstrip("/") for d in f["traj_q"].dims][0]
    values = f[pname][...]
    q = f["traj_q"][...]
    samples = q.reshape(len(values), -1, q.shape[-1])[:, :, -kept:]
    x = np.repeat(values, samples.shape[1] * samples.shape[2])
    fig, ax = plt.subplots(figsize=(10, 5), layout="constrained")
    ax.plot(x, samples.ravel(), ",", color="k", alpha=0.6)
    ax.set(xlabel=pname, ylabel="q at t = 2πk/Ω",
           title=f"last {kept} of {q.shape[-1]} stroboscopic samples of {samples.shape[1]} starts per {pname}")
    fig.suptitle(text(f, "title"), fontsize=10)
    save_figure(fig, path, dpi=130)
    plt.close(fig)
    return f"{len(values)} values of {pname}, {samples.shape[1]} starts each, {kept} samples kept"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--in", dest="src", default="out")
    parser.add_argument("--out", default="out/figures")
    args = parser.parse_args()
    src, out = Path(args.src), Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    jobs = [("basins_van_der_pol", van_der_pol, ()),
            ("basins_forced_duffing_autonomous", forced_autonomous, ("basins_forced_duffing",)),
            ("basins_forced_duffing_chaos", forced_chaos, ()),
            ("basins_lorenz", lorenz, ()),
            ("orbit_diagram_duffing", orbit_diagram, ())]
    for name, draw, others in jobs:
        files = [src / f"{n}.h5" for n in (name,) + others]
        missing = [str(p) for p in files if not p.exists()]
        if missing:
            print(f"{name}: skipped, no {', '.join(missing)}")
            continue
        handles = [h5py.File(p, "r") for p in files]
        try:
            print(f"{out / (name + '.png')}: {draw(*handles, out / (name + '.png'))}")
        finally:
            for h in handles:
                h.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
