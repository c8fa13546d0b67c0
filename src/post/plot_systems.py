#!/usr/bin/python3
"""Figures of the field's systems written as K in the spec (sweeps/forced_duffing.toml, ...).

  plot_systems.py OUT_DIR FILE.h5 [FILE.h5 ...]

Each file is drawn by its root attribute `scene` (the spec's label) and written to
OUT_DIR/<label>.png; the numbers the figure shows are printed. Labels:
  forced_duffing   final states on the stroboscopic section: which periodic orbit each start ends on
  spin_orbit       final spin rate against the initial one: capture into the 1:1 and 3:2 resonances
  kepler_perturbed the orbit and its energy; ln λ against its closed form α(1 − cos θt)/θ
  lane_emden_5     θ(t) against the exact (1 + t²/3)^(−1/2), and the error
"""
import argparse
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")  # batch jobs and CI have no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from plot_maps import centers_extent  # noqa: E402  (lives next to this script)
from safe_output import save_figure  # noqa: E402


def attr(f, name):
    value = f.attrs[name]
    return value.decode() if isinstance(value, bytes) else value


def parameter(f, name):
    """A scene parameter's value from the spec stored in the file (K's parameters are not axes)."""
    import tomllib
    return float(tomllib.loads(attr(f, "spec"))["scene"][name])


def forced_duffing(f, path):
    q, p = f["final_q"][...], f["final_p"][...]
    q0, p0 = f["q_0"][...], f["p_0"][...]
    # The section points of the periodic orbits: final states rounded to 1e-3 (they agree to
    # ~1e-9 once a start has settled), most frequent first.
    points, counts = np.unique(np.round(np.c_[q.ravel(), p.ravel()], 3), axis=0,
                               return_counts=True)
    order = np.argsort(-counts)
    points, counts = points[order], counts[order]
    label = np.full(q.shape, len(points), dtype=float)
    for k, (a, b) in enumerate(points):
        label[(np.abs(q - a) < 5e-3) & (np.abs(p - b) < 5e-3)] = k
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained")
    ax.imshow(label.T, origin="lower", aspect="auto", cmap="coolwarm", interpolation="nearest",
              extent=centers_extent(q0) + centers_extent(p0))
    ax.set(xlabel="q₀", ylabel="p₀", title="which periodic orbit each start ends on")
    bx.plot(q.ravel(), p.ravel(), ".", ms=2, alpha=0.3, color="0.4")
    for k, (a, b) in enumerate(points[:4]):
        bx.plot(a, b, "o", ms=9, label=f"orbit {k + 1}: ({a:.3f}, {b:.3f}), {counts[k]} starts")
    bx.set(xlabel="q", ylabel="p", title=f"final states at t = {attr(f, 't_end'):g} (stroboscopic)")
    bx.legend(loc="best", fontsize=8)
    fig.suptitle("Forced damped Duffing: " + attr(f, "K"), fontsize=9)
    save_figure(fig, path, dpi=100)
    share = ", ".join(f"({a:.3f}, {b:.3f}): {c / q.size:.1%}" for (a, b), c in zip(points, counts))
    print(f"forced_duffing: {len(points)} section points: {share}")


def spin_orbit(f, path):
    p = f["final_p"][...]  # dims (p_0, q_0)
    p0, q0 = f["p_0"][...], f["q_0"][...]
    e = parameter(f, "e")
    # The tidal torque's equilibrium ν(e) = N(e)/L(e) (Celletti & Chierchia 2008), as in the spec.
    nu = (1 + 15 * e**2 / 2 + 45 * e**4 / 8 + 5 * e**6 / 16) / (
        (1 + 3 * e**2 + 3 * e**4 / 8) * (1 - e**2) ** 1.5)
    fig, ax = plt.subplots(figsize=(7, 4.4), layout="constrained")
    colors = plt.cm.viridis(np.linspace(0, 1, len(q0)))
    for j, c in enumerate(colors):
        ax.plot(p0, p[:, j], ".", ms=3, color=c, label=f"q₀ = {q0[j]:.2f}" if j in (0, len(q0) - 1) else None)
    for level, name in [(1.0, "1:1"), (1.5, "3:2"), (nu, "ν(e)")]:
        ax.axhline(level, color="k", lw=0.6, ls="--")
        ax.text(p0[0], level, f" {name}", va="bottom", fontsize=8)
    ax.set(xlabel="initial spin rate p₀", ylabel=f"spin rate p at t = {attr(f, 't_end'):.0f}",
           title=f"Spin–orbit with tidal dissipation (e = {e}): capture into resonances")
    ax.legend(loc="upper left", fontsize=8)
    save_figure(fig, path, dpi=100)
    near = lambda x: float(np.mean(np.abs(p - x) < 0.02))  # noqa: E731
    print(f"spin_orbit: in 1:1 {near(1.0):.1%}, in 3:2 {near(1.5):.1%}, "
          f"elsewhere {1 - near(1.0) - near(1.5):.1%} (nu(e) = {nu:.4f})")


def kepler_perturbed(f, path):
    t = f["t"][...]
    q1, q2 = f["traj_q1"][...].reshape(-1), f["traj_q2"][...].reshape(-1)
    log_lambda = f["traj_log_lambda"][...].reshape(-1)
    alpha, theta = parameter(f, "alpha"), parameter(f, "theta")
    exact = alpha * (1 - np.cos(theta * t)) / theta
    error = np.max(np.abs(log_lambda - exact))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained")
    ax.plot(q1, q2, lw=0.5)
    ax.plot(0, 0, "k*")
    ax.set(xlabel="q₁", ylabel="q₂", aspect="equal", title="the orbit, t ≤ %g" % t[-1])
    p1, p2 = f["traj_p1"][...].reshape(-1), f["traj_p2"][...].reshape(-1)
    energy = (p1**2 + p2**2) / 2 - 1 / np.hypot(q1, q2)
    bx.plot(t, energy, lw=1)
    bx.set(xlabel="t", ylabel="E = |p|²/2 − 1/|q|",
           title=f"Kepler energy, pumped and damped by α sin(θt)\n"
                 f"ln λ = α(1 − cos θt)/θ to {error:.1e}")
    fig.suptitle("Time-perturbed Kepler problem: " + attr(f, "K"), fontsize=9)
    save_figure(fig, path, dpi=100)
    print(f"kepler_perturbed: ln lambda error {error:.2e}, H from {f['traj_H'][...].reshape(-1)[0]:.6f} "
          f"to {f['traj_H'][...].reshape(-1)[-1]:.6f}")


def lane_emden(f, path):
    t = f["t"][...]
    q = f["traj_q"][...].reshape(-1)
    exact = (1 + t**2 / 3) ** -0.5
    error = np.abs(q - exact)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.0), layout="constrained")
    ax.plot(t, q, lw=1.5, label=f"{attr(f, 'method')}, h = {attr(f, 'h'):g}")
    ax.plot(t[::5], exact[::5], "k.", ms=3, label="(1 + t²/3)^(−1/2)")
    ax.set(xlabel="t", ylabel="θ", title="Lane–Emden n = 5 from t = %g" % t[0])
    ax.legend(fontsize=8)
    bx.semilogy(t[1:], error[1:])
    bx.set(xlabel="t", ylabel="|θ − exact|", title=f"error (largest {error.max():.1e})")
    save_figure(fig, path, dpi=100)
    print(f"lane_emden_5: largest error {error.max():.2e}")


DRAW = {"forced_duffing": forced_duffing, "spin_orbit": spin_orbit,
        "kepler_perturbed": kepler_perturbed, "lane_emden_5": lane_emden}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", type=Path)
    parser.add_argument("files", type=Path, nargs="+")
    args = parser.parse_args()
    args.out_dir.mkdir(parents=True, exist_ok=True)
    for path in args.files:
        with h5py.File(path, "r") as f:
            label = attr(f, "scene")
            if label not in DRAW:
                sys.exit(f"{path}: scene '{label}' has no figure here; known: {', '.join(DRAW)}")
            DRAW[label](f, args.out_dir / f"{label}.png")


if __name__ == "__main__":
    main()
