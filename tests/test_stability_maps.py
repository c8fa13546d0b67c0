#!/usr/bin/python3
"""Runs src/post/stability_maps.py --quick with a real contactsweep and checks what it measures:

* damped oscillator (omega = 1): each method's first unstable step size at gamma = 0.1 is the first
  grid h past the linear-theory limit (THEORY_LIMIT_A, eigenvalues of the one-step map,
  tests/test_stability.cpp); at gamma = 0 and 0.5 (THEORY_LIMITS) it is at most one grid h
  further (the h grid is fine only near the gamma = 0.1 limits); contact_splitting6's stable
  island at gamma = 0.1 is found at the theory's [3.1784, 3.2398];
* damped double well from q0 = 2 (shared/PHYSICS.md): the hybrid leap-frog ends in the left well,
  as the reference does, at small h; wrong well from h ~ 0.254, blow-up from h ~ 0.431; at
  h = 0.01 no method puts any q0 of the axis in the other well than the reference;
* both PNGs exist and are real images.

  /usr/bin/python3 tests/test_stability_maps.py CONTACTSWEEP_BINARY
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import matplotlib.image
import numpy as np

POST = Path(__file__).resolve().parent.parent / "src" / "post"
sys.path.insert(0, str(POST))
sys.dont_write_bytecode = True  # runs in the source tree: leave no __pycache__ behind
from stability_maps import THEORY_LIMIT_A, THEORY_LIMITS, GROWTH, load  # noqa: E402

ROUNDING = 1e-4  # the theory limits are given to 4 decimals
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def number(text):
    return np.inf if text == "none" else float(text)


def first_unstable(ds, gamma):
    """(h axis, index of the first unstable h) at this gamma: diverged, broke down or grew."""
    row = ds.sel(gamma=gamma, method="nearest")
    bad = (row.status.values != 0) | (np.abs(row.final_q.values) > GROWTH)  # q0 = 1
    return ds.h.values, int(np.argmax(bad)) if bad.any() else None


def check_oscillator(out, text):
    lines = {m[1]: m for m in re.finditer(
        r"limit A (\w+): first diverged h = (\S+), largest stable h below = (\S+), "
        r"first grown h = (\S+), largest decaying h below = (\S+) \(gamma = 0\.1\)(.*)", text)}
    check(sorted(lines) == sorted(THEORY_LIMIT_A), f"a 'limit A' line per method: {sorted(lines)}")
    for m, theory in THEORY_LIMIT_A.items():
        if m not in lines:
            continue
        diverged, grown, below = (float(lines[m][i]) for i in (2, 4, 5))
        check(below <= theory + ROUNDING < grown + 2 * ROUNDING,
              f"{m}: gamma = 0.1 limit {theory} lies in (largest stable {below:.4f}, "
              f"first unstable {grown:.4f}]")
        check(grown - below < 0.003 and grown <= diverged,
              f"{m}: adjacent grid step sizes around the limit ({grown - below:.4f} apart), "
              f"growth flagged no later than divergence ({diverged:.4f})")
        ds = load(out / f"stability_h_gamma_{m}.h5")
        h, i = first_unstable(ds, 0.1)
        check(i is not None and abs(h[i] - grown) < 1e-6,
              f"{m}: the printed limit is the file's first unstable h at gamma = 0.1")
        for gamma in (0.0, 0.5):
            limit = THEORY_LIMITS[gamma][m]
            h, i = first_unstable(ds, gamma)
            skipped = int(((h > limit + ROUNDING) & (h < h[i])).sum()) if i is not None else -1
            check(i is not None and h[i] >= limit - ROUNDING and skipped <= 1,
                  f"{m}: gamma = {gamma}: first unstable h = {h[i] if i is not None else None:.4f} "
                  f"at most one grid h past the theory's {limit} ({skipped} between)")
        if m == "contact_splitting6":
            island = re.search(r"stable again on \[(\S+), (\S+)\]", lines[m][6])
            a, b = (float(island[1]), float(island[2])) if island else (np.nan, np.nan)
            check(3.17837 - ROUNDING <= a < 3.17837 + 0.003 and 3.23982 - 0.004 < b <= 3.23982 + ROUNDING,
                  f"{m}: stable island at gamma = 0.1 measured [{a}, {b}], theory [3.1784, 3.2398]")


def check_double_well(out, text):
    any_q0 = {m[1]: (number(m[2]), number(m[3])) for m in re.finditer(
        r"limit C (\w+): first wrong-well h = (\S+), first blow-up h = (\S+)", text)}
    from_2 = {m[1]: (number(m[2]), number(m[3])) for m in re.finditer(
        r"double well from q0 = 2 (\w+): first wrong-well h = (\S+), first blow-up h = (\S+)", text)}
    check(sorted(any_q0) == sorted(THEORY_LIMIT_A) == sorted(from_2), "double-well lines per method")
    # shared/PHYSICS.md, measured with the hybrid leap-frog from q0 = 2: wrong well from
    # h ~ 0.254, blow-up from h ~ 0.431 (the quick h axis has every third h: steps of ~0.003 there).
    wrong, blow = from_2.get("hybrid_leapfrog", (np.nan, np.nan))
    check(0.245 <= wrong <= 0.262, f"hybrid_leapfrog from q0 = 2: wrong well from h = {wrong} (~0.254)")
    check(0.425 <= blow <= 0.44, f"hybrid_leapfrog from q0 = 2: blow-up from h = {blow} (~0.431)")
    for m, (wrong, blow) in any_q0.items():
        check(0.01 < min(wrong, blow), f"{m}: neither wrong well nor blow-up at h = 0.01 on the "
                                       f"whole q0 axis (first at {wrong}, {blow})")

    m = re.search(r"(\d+) of (\d+) labels change at h = [\d.e-]+; undecided: (\d+)", text)
    check(m is not None and int(m[1]) == 0 and int(m[3]) == 1,
          "reference labels unchanged at half its step; only q0 = 0 (on the saddle) undecided")
    ref_ds = load(next(out.glob("stability_h_q0_reference_h0.002.h5")))
    ref = ref_ds.basin.isel(h=0)
    hyb = load(out / "stability_h_q0_hybrid_leapfrog.h5")
    i2 = int(np.argmin(abs(hyb.q_0.values - 2.0)))
    check(abs(hyb.q_0.values[i2] - 2.0) < 1e-12 and int(ref.values[i2]) == -1,
          "q0 = 2 is on the axis, and the reference ends in the left well from it")
    small = hyb.h.values < 0.2
    b2 = hyb.basin.isel(q_0=i2).values[small]
    s2 = hyb.status.isel(q_0=i2).values[small]
    check(bool((b2 == -1).all() and (s2 == 0).all()),
          f"hybrid_leapfrog from q0 = 2 ends in the left well at every h < 0.2 ({small.sum()} step sizes)")
    for m in THEORY_LIMIT_A:
        ds = load(out / f"stability_h_q0_{m}.h5").sel(h=0.01)
        ok = (ds.status.values == 0) & (ds.basin.values == ref.values)
        check(bool(ok.all()), f"{m}: at h = 0.01 every q0 ends where the reference does "
                              f"({int((~ok).sum())} differ)")


def check_png(path):
    ok = path.is_file() and path.stat().st_size > 20_000
    if ok:
        image = matplotlib.image.imread(path)
        ok = image.shape[0] > 500 and image.shape[1] > 800 and float(image[..., :3].std()) > 0.05
    check(ok, f"{path.name} is a real chart")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        proc = subprocess.run([sys.executable, str(POST / "stability_maps.py"), "--bin", sys.argv[1],
                               "--out", str(out), "--quick"], capture_output=True, text=True)
        print(proc.stdout, proc.stderr, sep="\n")
        check(proc.returncode == 0, f"stability_maps.py --quick exits 0 (got {proc.returncode})")
        if proc.returncode == 0:
            check_oscillator(out, proc.stdout)
            check_double_well(out, proc.stdout)
            check_png(out / "stability_h_gamma.png")
            check_png(out / "stability_h_q0.png")
    print(f"{len(failures)} failed" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
