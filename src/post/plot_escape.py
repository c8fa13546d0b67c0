#!/usr/bin/python3
"""Exit basins and escape times of an open system (measures.stop with exits and basin;
docs/observables.md).

  plot_escape.py OUT_DIR FILE.h5 [FILE.h5 ...]

Each file becomes OUT_DIR/<file stem>.png: left the basin map over its last two grid axes, the
exits (attractor_period -1, channel in the first attractor coordinate) and the attractors of the
lanes that never stopped in one colour each, with fractions, S_b, S_bb and the uncertainty
exponent; right the escape-time map (stop_time, log scale; trapped lanes grey).
"""
import math
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap, LogNorm  # noqa: E402

from plot_maps import centers_extent  # noqa: E402  (lives next to this script)
from safe_output import save_figure  # noqa: E402


def text(f, name):
    value = f.attrs[name]
    return value.decode() if isinstance(value, bytes) else str(value)


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for name in sys.argv[2:]:
        with h5py.File(name, "r") as f:
            xname, yname = [d[0].name.lstrip("/") for d in f["basin"].dims][-2:]
            extent = centers_extent(f[xname][...]) + centers_extent(f[yname][...])
            labels = [int(l) for l in f["attractor_label"][...]]
            periods = f["attractor_period"][...]
            # an exit's channel is in the first position's column (docs/observables.md)
            first = "attractor_q1" if "attractor_q1" in f else "attractor_q"
            fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.2), layout="constrained")
            palette = plt.get_cmap("tab10")
            colour = ["0.15"] + [palette(k % 10) for k in range(len(labels))]
            codes = {l: k + 1 for k, l in enumerate(labels)}
            index = np.vectorize(lambda l: codes.get(int(l), 0))(f["basin"][...])
            ax.imshow(index.T, origin="lower", aspect="auto", interpolation="nearest",
                      cmap=ListedColormap(colour), vmin=-0.5, vmax=len(labels) + 0.5, extent=extent)
            for k, l in enumerate(labels):
                kind = (f"exit {int(f[first][k])}" if periods[k] == -1 else "attractor")
                ax.plot([], [], "s", color=colour[k + 1],
                        label=f"{l}: {kind} {f['attractor_fraction'][k]:.3f}")
            ax.plot([], [], "s", color=colour[0], label="0: undecided")
            ax.legend(fontsize=8, loc="upper right")
            ax.set(xlabel=xname, ylabel=yname,
                   title=f"S_b = {f.attrs['basin_entropy']:.3f}, S_bb = "
                         f"{f.attrs['boundary_basin_entropy']:.3f} "
                         f"({'>' if f.attrs['boundary_basin_entropy'] > math.log(2) else '≤'} ln 2), "
                         f"α = {f.attrs['uncertainty_exponent']:.2f}")
            stop = f["stop_time"][...]
            bx.imshow(np.where(np.isnan(stop), 1.0, 0.0).T, origin="lower", aspect="auto",
                      cmap=ListedColormap(["white", "0.6"]), extent=extent, interpolation="nearest")
            positive = stop[np.isfinite(stop) & (stop > 0)]
            norm = LogNorm(vmin=max(positive.min(), 1e-2), vmax=positive.max()) if positive.size else None
            image = bx.imshow(np.ma.masked_invalid(stop).T, origin="lower", aspect="auto",
                              interpolation="nearest", cmap="viridis", norm=norm, extent=extent)
            fig.colorbar(image, ax=bx, label="escape time (stop_time)")
            bx.set(xlabel=xname, ylabel=yname, title="escape time (grey: trapped)")
            fig.suptitle(text(f, "title"), fontsize=10)
            path = out / (Path(name).stem + ".png")
            save_figure(fig, path, dpi=100)
            plt.close(fig)
            escaped = np.isfinite(stop).mean()
            print(f"{path}: escaped {escaped:.4f}; " + ", ".join(
                f"{l}: {'exit' if p == -1 else 'attractor'} {x:.4f}"
                for l, p, x in zip(labels, periods, f["attractor_fraction"][...])))


if __name__ == "__main__":
    main()
