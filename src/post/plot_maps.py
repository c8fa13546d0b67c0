#!/usr/bin/python3
"""Basin and synchronization maps from contactsweep output.

  plot_maps.py --in out --out out/figures [--eps 5]

basins_double_well.h5 (grid q_0 x p_0, measure `basin`) -> basins_double_well.png, and prints the
basin fractions, the basin entropy S_b and the boundary basin entropy S_bb (Daza et al. 2016).
sync_g_gamma.h5 (grid g x gamma, measure `sync`) -> sync_g_gamma.png.
lyapunov_duffing.h5 (grid F x Omega, measure `lyapunov`) -> lyapunov_duffing.png.
Files that do not exist are skipped; if neither exists there is nothing to do (exit 0).
"""
import argparse
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import LogNorm, Normalize, to_rgb  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from basin_entropy import basin_entropy  # noqa: E402  (lives next to this script)
from safe_output import save_figure  # noqa: E402

STATUS_NAMES = {1: "diverged", 2: "integrator breakdown", 3: "non-finite output",
                4: "K undefined at the initial state"}
BASIN_COLORS = {-1: to_rgb("tab:blue"), 1: to_rgb("tab:red"), 0: (0.55, 0.55, 0.55)}
BASIN_NAMES = {-1: "left well (−1)", 1: "right well (+1)", 0: "undecided (0)"}


def report_status(ds, name):
    """Failed cells are results, not errors, but a user must hear about them."""
    if "status" not in ds:
        return
    s = ds.status.fillna(0).values.astype(int)
    if np.any(s != 0):
        counts = ", ".join(f"{STATUS_NAMES.get(int(c), f'status {int(c)}')}: {int((s == c).sum())}"
                           for c in np.unique(s[s != 0]))
        print(f"{name}: {int((s != 0).sum())} of {s.size} cells failed ({counts})")


def centers_extent(x):
    """imshow extent that puts pixel centres on the grid values (grids are linspace)."""
    x = np.asarray(x, dtype=float)
    d = (x[-1] - x[0]) / (len(x) - 1) if len(x) > 1 else 1.0
    return [x[0] - d / 2, x[-1] + d / 2]


def basin_map(ds, out, eps):
    basin = ds.basin
    xdim = "q_0" if "q_0" in basin.dims else basin.dims[0]
    ydim = [d for d in basin.dims if d != xdim][0]
    # fillna: if the writer declares a _FillValue, xarray turns those cells into NaN (undecided)
    b = basin.fillna(0).transpose(ydim, xdim).values.astype(int)
    t = ds.settle_time.transpose(ydim, xdim).values if "settle_time" in ds else np.full(b.shape, np.nan)

    # Colour by basin, then mix towards white by settle time: lighter = settles later.
    finite = np.isfinite(t)
    t0, t1 = (np.nanmin(t), np.nanmax(t)) if finite.any() else (0.0, 1.0)
    lightness = np.where(finite, (t - t0) / (t1 - t0 if t1 > t0 else 1.0), 0.0)
    base = np.zeros(b.shape + (3,))
    for label, c in BASIN_COLORS.items():
        base[b == label] = c
    rgb = base + (1 - base) * 0.75 * lightness[..., None]

    fractions = {label: float((b == label).mean()) for label in (-1, 1, 0)}
    be = basin_entropy(b, eps)
    print("basins: " + ", ".join(f"{BASIN_NAMES[k].split(' (')[0]} {v:.4f}" for k, v in fractions.items()))
    print(f"basin entropy (eps = {eps}x{eps} cells, {be.n_boxes} boxes, {be.n_boundary_boxes} on a boundary): "
          f"S_b = {be.S_b:.4f}, S_bb = {be.S_bb:.4f}")
    print(f"log 2 criterion: S_bb > ln 2 = {math.log(2):.4f}: "
          f"{'yes -> the boundary is fractal' if be.fractal_by_log2 else 'no (inconclusive)'}")

    fig, ax = plt.subplots(figsize=(7.5, 6))
    ax.imshow(rgb, origin="lower", aspect="auto", interpolation="nearest",
              extent=centers_extent(ds[xdim]) + centers_extent(ds[ydim]))
    ax.set(xlabel=label_of(ds[xdim]), ylabel=label_of(ds[ydim]),
           title=f"{ds.attrs.get('title', 'Basins of attraction')}\n"
                 f"S_b = {be.S_b:.3f}, S_bb = {be.S_bb:.3f} (ε = {eps})")
    ax.legend(handles=[Patch(color=BASIN_COLORS[k], label=f"{BASIN_NAMES[k]}: {fractions[k]:.1%}")
                       for k in (-1, 1, 0)], loc="upper right", fontsize="small", framealpha=0.85)
    sm = plt.cm.ScalarMappable(norm=Normalize(t0, t1), cmap="Greys_r")
    fig.colorbar(sm, ax=ax, label="settle time (lighter = later)")
    save(fig, out / "basins_double_well.png")


def sync_map(ds, out):
    # Short titles and colour-bar labels: the datasets' long_names are sentences, which overlapped
    # one another and were cut off at the figure's edge.
    panels = [("sync_r", "phase-locking value r", "r", dict(cmap="viridis", vmin=0, vmax=1)),
              ("sync_phase_drift", "phase drift d(θ₁ − θ₂)/dt", "rad / time",
               dict(cmap="coolwarm", center=0)),
              ("sync_freq_ratio", "frequency ratio ω₁/ω₂ (measured)", "ω₁/ω₂",
               dict(cmap="coolwarm", center=1)),
              ("sync_amplitude", "smaller amplitude at the window's end", "amplitude",
               dict(cmap="magma"))]
    panels = [(n, title, unit, kw) for n, title, unit, kw in panels if n in ds]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5), squeeze=False, layout="constrained")
    for ax, (name, title, unit, kw) in zip(axes.flat, panels):
        da = ds[name].squeeze()
        if da.ndim != 2:
            print(f"sync map: {name} has dims {da.dims}, need two; skipped", file=sys.stderr)
            continue
        if name == "sync_amplitude":  # decays by orders of magnitude with gamma: log scale
            v = da.values[np.isfinite(da.values) & (da.values > 0)]
            if v.size and v.max() > 100 * v.min():
                kw = dict(kw, norm=LogNorm(v.min(), v.max()))
        da.plot.pcolormesh(ax=ax, x=da.dims[0], y=da.dims[1], cbar_kwargs={"label": unit},
                           **kw)  # cells centred on the grid
        ax.set_title(title, fontsize="medium")
        ax.set_xlabel(da.dims[0])
        ax.set_ylabel(da.dims[1])
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    fig.suptitle(ds.attrs.get("title", "Synchronization map"))
    save(fig, out / "sync_g_gamma.png")


def lyapunov_map(ds, out):
    # Diverging colours centred on 0: chaos (> 0) red, periodic motion (< 0) blue.
    da = ds["lyapunov"].squeeze()
    fig, ax = plt.subplots(figsize=(7, 5.5), layout="constrained")
    limit = float(np.nanmax(np.abs(da.values)))
    da.plot.pcolormesh(ax=ax, x=da.dims[0], y=da.dims[1], cmap="RdBu_r", vmin=-limit, vmax=limit,
                       cbar_kwargs={"label": "largest Lyapunov exponent [1/time]"})
    ax.set_title(ds.attrs.get("title", "Lyapunov map"), fontsize="medium")
    ax.set_xlabel(da.dims[0])  # the coordinates' long_name of a K parameter says no more
    ax.set_ylabel(da.dims[1])
    print(f"lyapunov map: {float((da.values > 0.01).mean()):.1%} of the cells above 0.01")
    save(fig, out / "lyapunov_duffing.png")


def label_of(coord):
    name = coord.attrs.get("long_name", coord.name)
    return f"{name} [{coord.attrs['units']}]" if "units" in coord.attrs else name


def save(fig, path):
    if fig.get_layout_engine() is None:
        fig.tight_layout()
    save_figure(fig, path, dpi=120)
    plt.close(fig)
    print(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--in", dest="indir", type=Path, required=True, help="directory with the .h5 files")
    ap.add_argument("--out", dest="outdir", type=Path, required=True, help="directory for the PNGs")
    ap.add_argument("--eps", type=int, default=5, help="box size in cells for the basin entropy")
    args = ap.parse_args()
    args.outdir.mkdir(parents=True, exist_ok=True)

    for name, plot in (("basins_double_well", lambda ds: basin_map(ds, args.outdir, args.eps)),
                       ("sync_g_gamma", lambda ds: sync_map(ds, args.outdir)),
                       ("lyapunov_duffing", lambda ds: lyapunov_map(ds, args.outdir))):
        path = args.indir / f"{name}.h5"
        if not path.exists():
            print(f"plot_maps: no {path}, skipped")
            continue
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
        report_status(ds, name)
        plot(ds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
