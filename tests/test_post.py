#!/usr/bin/python3
"""Tests of the post-processing scripts in src/post, without the simulator: tiny HDF5 files in the
documented output layout (shared INTERFACE.md: coordinates as dimension scales, root attributes)
are written with h5py, both plot scripts run on them, and the basin entropy is checked against
values known in closed form. Exit status 0 on success.

  /usr/bin/python3 tests/test_post.py
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import h5py
import matplotlib.image
import numpy as np

POST = Path(__file__).resolve().parent.parent / "src" / "post"
sys.path.insert(0, str(POST))
sys.dont_write_bytecode = True  # runs in the source tree: leave no __pycache__ behind
from basin_entropy import basin_entropy, self_check  # noqa: E402


def write_h5(path, spec, coords, data, **attrs):
    """coords: {name: values}; data: {name: (dims, values, attrs)} as contactsweep writes them."""
    with h5py.File(path, "w") as f:
        root = dict(title=spec.splitlines()[0].partition("=")[2].strip(' "'), spec=spec,
                    scene=re.search(r'name = "(\w+)"', spec)[1], method="hybrid_leapfrog", h=0.01,
                    t_end=float(coords["t"][-1]) if "t" in coords else 10.0,
                    contactsweep_version="0.1.0", Conventions="CF-1.8", history="test_post.py")
        for k, v in {**root, **attrs}.items():
            f.attrs[k] = v
        for name, values in coords.items():
            d = f.create_dataset(name, data=np.asarray(values, dtype=float))
            d.make_scale(name)
            d.attrs["long_name"] = "time" if name == "t" else f"initial value or parameter {name}"
        for name, (dims, values, a) in data.items():
            d = f.create_dataset(name, data=values)
            assert d.ndim == len(dims), name
            for i, dim in enumerate(dims):
                d.dims[i].attach_scale(f[dim])
            for k, v in a.items():
                d.attrs[k] = v


def spec_text(title, scene, **params):
    lines = [f'title = "{title}"', "", "[scene]", f'name = "{scene}"']
    lines += [f"{k} = {v}" for k, v in params.items()]
    return "\n".join(lines + ["", "[integrator]", 'method = "hybrid_leapfrog"', "h = 0.01", ""])


def make_paper_files(d):
    t = np.linspace(0, 50, 501)
    for name, scene, decay in (("paper_fig1a", "damped_oscillator", 0.05),
                               ("paper_fig1b", "z2_damping", 0.02)):
        write_h5(d / f"{name}.h5", spec_text(name, scene, omega=1.0, gamma=0.1), {"t": t},
                 {"traj_q": (("t",), np.exp(-decay * t) * np.cos(t), {"long_name": "q"})})
    q0 = np.array([-2.0, 2.0])
    q = np.sign(q0)[:, None] * (1 + np.exp(-t / 10) * np.cos(1.4 * t))[None, :]  # exact mirrors
    write_h5(d / "paper_fig2.h5", spec_text("paper_fig2", "double_well", a=1.0, gamma=0.1),
             {"q_0": q0, "t": t}, {"traj_q": (("q_0", "t"), q, {"long_name": "q"}),
                                   "status": (("q_0",), np.zeros(2, np.uint8), {})})
    g = np.array([0.0, 0.8])
    t = np.linspace(0, 100, 1001)
    q1 = np.stack([np.cos(math.sqrt(1.2) * t), np.cos(t)])
    q2 = np.stack([-np.cos(math.sqrt(0.8) * t), -np.cos(t + 0.3)])
    write_h5(d / "paper_fig3.h5", spec_text("paper_fig3", "coupled_oscillators", omega1_sq=1.2,
                                            omega2_sq=0.8, gamma=0.01),
             {"g": g, "t": t}, {"traj_q1": (("g", "t"), q1, {}), "traj_q2": (("g", "t"), q2, {})})


def make_map_files(d):
    qg, pg = np.linspace(-3, 3, 60), np.linspace(-2, 2, 40)
    Q, P = np.meshgrid(qg, pg, indexing="ij")          # dims (q_0, p_0)
    basin = np.where(Q + 0.8 * np.sin(3 * P) < 0, -1, 1).astype(np.int8)
    basin[np.hypot(Q, P) < 0.3] = 0                    # undecided near the saddle
    settle = np.where(basin != 0, 5 + 10 * np.abs(P) + np.abs(Q), np.nan)
    status = np.zeros(basin.shape, np.uint8)
    status[0, :3] = 1
    basin[0, :3] = 0
    settle[0, :3] = np.nan
    write_h5(d / "basins_double_well.h5", spec_text("Basins of the damped double well", "double_well"),
             {"q_0": qg, "p_0": pg},
             {"basin": (("q_0", "p_0"), basin, {"long_name": "basin", "flag_values": np.int8([-1, 0, 1]),
                                                "flag_meanings": "left_well undecided right_well",
                                                "_FillValue": np.int8(0)}),  # decodes to NaN
              "settle_time": (("q_0", "p_0"), settle, {"long_name": "settle time"}),
              "status": (("q_0", "p_0"), status, {"long_name": "run status"})})

    g, gamma = np.linspace(0, 1, 9), np.linspace(0.001, 0.1, 7)
    G, Gm = np.meshgrid(g, gamma, indexing="ij")       # dims (g, gamma)
    write_h5(d / "sync_g_gamma.h5", spec_text("Sync map", "coupled_oscillators"), {"g": g, "gamma": gamma},
             {"sync_r": (("g", "gamma"), np.clip(G * 1.5, 0, 1), {"long_name": "phase-locking value"}),
              "sync_phase_drift": (("g", "gamma"), 0.2 * (0.5 - G), {"long_name": "phase drift"}),
              "sync_freq_ratio": (("g", "gamma"), 1 + 0.2 * (1 - G), {"long_name": "frequency ratio"}),
              "sync_amplitude": (("g", "gamma"), np.exp(-Gm * 100), {"long_name": "amplitude"}),
              "status": (("g", "gamma"), np.zeros(G.shape, np.uint8), {})})
    return basin


def run(script, indir, outdir):
    r = subprocess.run([sys.executable, str(POST / script), "--in", str(indir), "--out", str(outdir)],
                       capture_output=True, text=True, env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})
    print(r.stdout, r.stderr, sep="", end="")
    return r


def check_png(path):
    """Exists, decodes, and is not a blank canvas."""
    assert path.is_file(), f"missing {path}"
    assert path.stat().st_size > 10_000, f"{path} is suspiciously small"
    img = matplotlib.image.imread(path)
    assert img.shape[0] > 300 and img.shape[1] > 300, img.shape
    assert img[..., :3].std() > 0.05, f"{path} is nearly uniform"


def test_basin_entropy():
    eps = 5
    # A checkerboard: every 5x5 box holds 13 cells of one label and 12 of the other, so every box
    # is a boundary box with S = H(13/25, 12/25) = 0.692347, just under ln 2 = 0.693147.
    i, j = np.indices((50, 50))
    r = basin_entropy((i + j) % 2, eps)
    h = -(13 / 25 * math.log(13 / 25) + 12 / 25 * math.log(12 / 25))
    assert r.n_boundary_boxes == r.n_boxes == 100 and math.isclose(r.S_b, h) and math.isclose(r.S_bb, h), r
    assert not r.fractal_by_log2  # two labels can never exceed ln 2
    # Vertical stripes of three labels (column mod 3): each 5-column box holds the labels in
    # shares (2, 2, 1)/5, so S_b = S_bb = H(0.4, 0.4, 0.2) = 1.054920 > ln 2: criterion met.
    r = basin_entropy(j % 3, eps)
    h = -(2 * 0.4 * math.log(0.4) + 0.2 * math.log(0.2))
    assert math.isclose(r.S_b, h) and math.isclose(r.S_bb, h) and r.fractal_by_log2, r
    # Straight boundary inside box column 4 (columns 20, 21 | 22, 23, 24): S_bb = H(0.4, 0.6) =
    # 0.673012 on the 10 boundary boxes of 100, S_b = 0.0673012; a single basin has S_b = 0.
    r = basin_entropy(np.where(j < 22, -1, 1), eps)
    h = -(0.4 * math.log(0.4) + 0.6 * math.log(0.6))
    assert r.n_boundary_boxes == 10 and math.isclose(r.S_bb, h) and math.isclose(r.S_b, h / 10), r
    r = basin_entropy(np.ones((50, 50)), eps)
    assert r.S_b == 0 and math.isnan(r.S_bb), r
    # Random maps against the exact multinomial expectation (see basin_entropy.self_check).
    self_check(verbose=True)


def test_plots():
    with tempfile.TemporaryDirectory() as tmp:
        indir, outdir = Path(tmp) / "in", Path(tmp) / "figures"
        indir.mkdir()

        # Nothing to read: the paper figures must fail loudly, the maps have nothing to do.
        assert run("plot_paper_figures.py", indir, outdir).returncode == 1
        r = run("plot_maps.py", indir, outdir)
        assert r.returncode == 0 and not list(outdir.glob("*.png")), r

        make_paper_files(indir)
        basin = make_map_files(indir)

        r = run("plot_paper_figures.py", indir, outdir)
        assert r.returncode == 0, r.stderr
        for name in ("fig1", "fig2", "fig3"):
            check_png(outdir / f"{name}.png")
        assert "max |q(t; -2) + q(t; 2)| = 0" in r.stdout, r.stdout  # the fake is an exact mirror

        r = run("plot_maps.py", indir, outdir)
        assert r.returncode == 0, r.stderr
        for name in ("basins_double_well", "sync_g_gamma"):
            check_png(outdir / f"{name}.png")
        left = float(re.search(r"left well ([0-9.]+)", r.stdout)[1])
        assert abs(left - (basin == -1).mean()) < 1e-4, (left, (basin == -1).mean())
        assert "3 of 2400 cells failed (diverged: 3)" in r.stdout, r.stdout
        assert re.search(r"S_b = [0-9.]+, S_bb = [0-9.]+", r.stdout), r.stdout
        assert "log 2 criterion" in r.stdout, r.stdout


def test_planted_links():
    """Outputs in a shared directory: a link planted at an output's name is replaced, never
    written through, and a directory there is refused by name."""
    import safe_output
    import work_precision_adaptive
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        indir, outdir = tmp / "in", tmp / "figures"
        indir.mkdir()
        outdir.mkdir()
        make_paper_files(indir)
        make_map_files(indir)
        victim = tmp / "victim.txt"
        victim.write_text("someone else's file\n")
        planted = {outdir / "fig1.png": victim, outdir / "basins_double_well.png": victim,
                   outdir / "fig2.png": tmp / "created_through_link"}  # a dangling one too
        for link, target in planted.items():
            link.symlink_to(target)
        assert run("plot_paper_figures.py", indir, outdir).returncode == 0
        assert run("plot_maps.py", indir, outdir).returncode == 0
        # The spec the work-precision charts hand the program, through its own code path.
        spec = tmp / "wp.toml"
        spec.write_text('title = "wp"\n[initial]\nq = 1.0\n[grid.h]\nvalues = [0.1, 0.2]\n')
        toml = outdir / "adaptive_wp.toml"
        toml.symlink_to(victim)
        planted[toml] = victim
        assert work_precision_adaptive.without_h_axis(spec, outdir) == toml
        assert tomllib.loads(toml.read_text())["grid"] == {"q_0": {"values": [1.0]}}, toml.read_text()

        assert victim.read_bytes() == b"someone else's file\n", victim.read_bytes()[:20]
        assert not (tmp / "created_through_link").exists()
        for link in planted:
            assert not link.is_symlink() and link.is_file(), link
            if link.suffix == ".png":
                check_png(link)
        mode = os.umask(0o022)
        os.umask(mode)
        assert (outdir / "fig1.png").stat().st_mode & 0o777 == 0o666 & ~mode  # as a file created by name
        # ... under any umask, not only the usual 022 (whose 0644 a fixed mode would also give):
        # a group project's 002 keeps the output group-writable, a private 077 keeps it private.
        for mask, expected in ((0o002, 0o664), (0o077, 0o600), (0o022, 0o644)):
            previous = os.umask(mask)
            try:
                safe_output.write_text(outdir / f"mode_{mask:03o}.txt", "text")
            finally:
                os.umask(previous)
            got = (outdir / f"mode_{mask:03o}.txt").stat().st_mode & 0o777
            assert got == expected, (oct(mask), oct(got))
        assert not list(outdir.glob(".*")), list(outdir.glob(".*"))  # no temporary file left

        # A directory at an output's name: refused, named, left as it was.
        (outdir / "fig3.png").unlink()
        (outdir / "fig3.png").mkdir()
        r = run("plot_paper_figures.py", indir, outdir)
        assert r.returncode == 1 and f"cannot write {outdir / 'fig3.png'}: it is a directory" in r.stderr, r
        assert (outdir / "fig3.png").is_dir() and not list((outdir / "fig3.png").iterdir())
        try:
            safe_output.write_text(outdir / "fig3.png", "text")
            raise AssertionError("a directory was written over")
        except SystemExit as e:
            assert str(e) == f"cannot write {outdir / 'fig3.png'}: it is a directory", e

        # A writer that fails leaves no temporary file and the old output as it was.
        def fail(f):
            f.write("partial")
            raise ValueError("writer failed")
        try:
            safe_output.write_output(toml, fail, text=True)
            raise AssertionError("the writer's error was swallowed")
        except ValueError:
            pass
        assert tomllib.loads(toml.read_text())["grid"] == {"q_0": {"values": [1.0]}}, toml.read_text()
        assert not list(outdir.glob(".*")), list(outdir.glob(".*"))


if __name__ == "__main__":
    test_basin_entropy()
    test_plots()
    test_planted_links()
    print("test_post: all passed")
