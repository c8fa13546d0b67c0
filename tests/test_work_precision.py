#!/usr/bin/python3
"""Runs src/post/work_precision.py --quick with the given contactsweep into a temporary directory
and checks the numbers it measured (work_precision.json) and the charts. Exit status 0 on success.

  /usr/bin/python3 tests/test_work_precision.py build/contactsweep

About 30 s on one core (most of it process launches of contactsweep).
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import matplotlib.image
import numpy as np

SCRIPT = Path(__file__).resolve().parent.parent / "src" / "post" / "work_precision.py"
ORDER_TOL = 0.3  # fitted slope against the nominal order, over >= 5 step sizes


def check(failures, ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def evals_to_reach(method_result, evals_per_step, t_end, tol):
    """Force evaluations per trajectory at the largest step size of the spec whose error is at
    most tol (inf if none is)."""
    h = np.array(method_result["h"])
    e = np.array([np.nan if x is None else x for x in method_result["error"]], dtype=float)
    ok = np.isfinite(e) & (e <= tol)
    return float(t_end / h[ok].max() * evals_per_step) if ok.any() else np.inf


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    binary = Path(sys.argv[1]).resolve()
    failures = []
    with tempfile.TemporaryDirectory(prefix="test_work_precision_") as tmp:
        out = Path(tmp)
        proc = subprocess.run([sys.executable, "-B", str(SCRIPT), "--bin", str(binary), "--out", str(out),
                               "--quick"], capture_output=True, text=True)
        print(proc.stdout[-3000:])
        if proc.returncode != 0:
            print(proc.stderr)
            sys.exit(f"work_precision.py failed with exit status {proc.returncode}")
        res = json.loads((out / "work_precision.json").read_text())
        nominal = res["methods"]
        traj = res["trajectories"]

        # Scene A has an exact solution: every method shows its order.
        for m, d in traj["damped_oscillator"]["methods"].items():
            o = nominal[m]["order"]
            check(failures, d["fit_points"] >= 5 and abs(d["order_fit"] - o) <= ORDER_TOL,
                  f"damped oscillator {m}: observed order {d['order_fit']:.3f} within {ORDER_TOL} of {o} "
                  f"({d['fit_points']} points)")

        # Double well: the reference's own error is far below every error the fit uses, and the
        # methods show their order there too. rk4's largest error component (p from q0 = 2) has a
        # small h^4 coefficient and falls like h^4.8 over this range: at least its order.
        dw = traj["double_well"]
        own = dw["reference"]["own_error"]
        fitted = [e for d in dw["methods"].values() for e in d["error"]
                  if e is not None and np.isfinite(e) and d["fit_range"][0] <= e <= d["fit_range"][1]]
        check(failures, 0 < own <= 0.05 * min(fitted),
              f"double-well reference's own error {own:.2e} <= 5 % of the smallest fitted error "
              f"{min(fitted):.2e}")
        for m, d in dw["methods"].items():
            o = nominal[m]["order"]
            ok = d["order_fit"] >= o - ORDER_TOL if m == "rk4" else abs(d["order_fit"] - o) <= ORDER_TOL
            check(failures, d["fit_points"] >= 5 and ok,
                  f"double well {m}: observed order {d['order_fit']:.3f} against {o} ({d['fit_points']} points)")

        # Cost in force evaluations (deterministic, unlike wall time, which belongs in the
        # benchmark numbers, not in assertions): at a tight tolerance the high-order composition
        # is cheaper than every second-order method, as its error falls like h^6 against h^2.
        tol = 1e-5
        for scene, r in traj.items():
            evals = {m: evals_to_reach(d, nominal[m]["evals_per_step"], r["t_end"], tol)
                     for m, d in r["methods"].items()}
            second = {m: e for m, e in evals.items() if nominal[m]["order"] == 2}
            check(failures, np.isfinite(min(second.values()))
                  and evals["contact_splitting6"] < min(second.values()),
                  f"{scene}: error <= {tol:g} costs contact_splitting6 {evals['contact_splitting6']:.3g} "
                  f"force evaluations, fewer than any 2nd-order method (cheapest "
                  f"{min(second.values()):.3g})")

        # dop853 over rtol: its error proportional to rtol (tolerance proportionality: slope 1 of
        # log error over log rtol, within ORDER_TOL, on its quick series 1e-5, 1e-7, 1e-9, all
        # far above the reference's and round-off's error), and on scene A below 10 rtol (1.7
        # rtol measured; the double well's crossings of its barrier amplify it to ~70 rtol); its
        # cost in attempts grows as rtol falls.
        for scene, r in traj.items():
            rows = r["adaptive"]["rows"]
            rtol = np.array([x["rtol"] for x in rows])
            err = np.array([x["error"] for x in rows])
            attempts = [x["attempts"] for x in rows]
            slope = float(np.polyfit(np.log(rtol), np.log(err), 1)[0])
            ok = abs(slope - 1.0) <= ORDER_TOL and all(a < b for a, b in zip(attempts, attempts[1:]))
            if scene == "damped_oscillator":
                ok = ok and (err <= 10 * rtol).all()
            check(failures, ok, f"{scene} dop853: error {err.tolist()} over rtol {rtol.tolist()} "
                  f"(slope {slope:.2f}), attempts {attempts}")
        for case in ("basins", "basins_magnetic_pendulum"):
            rows = res[case]["adaptive"]
            check(failures, len(rows) >= 2 and all(0.0 <= x["differ"] < 0.05 for x in rows),
                  f"{case} dop853: differing fractions {[x['differ'] for x in rows]}")

        # Basin maps: the hybrid leap-frog's map converges to the reference as h falls.
        b = res["basins"]
        rows = b["methods"]["hybrid_leapfrog"]
        f = [r["differ"] for r in rows]
        h = [r["h"] for r in rows]
        check(failures, h == sorted(h, reverse=True) and all(x > y for x, y in zip(f, f[1:])),
              f"hybrid_leapfrog basin map: differing fraction strictly falls with h: "
              + ", ".join(f"{a:g}: {c:.4f}" for a, c in zip(h, f)))
        check(failures, f[0] > 0.05 and f[-1] < 0.02,
              f"hybrid_leapfrog basin map: {f[0]:.3f} > 0.05 differ at h = {h[0]:g}, {f[-1]:.4f} < 0.02 "
              f"at h = {h[-1]:g}")
        check(failures, b["ref_diff"] < 0.1 * min(x for x in f if x > 0),
              f"basin reference against h/2: {b['ref_diff']:.2e} < 10 % of the smallest hybrid fraction")

        mp = res["basins_magnetic_pendulum"]
        hybrid = [r["differ"] for r in mp["methods"]["hybrid_leapfrog"]]
        check(failures, all(0.0 <= x < 0.5 for x in hybrid) and mp["ref_diff"] < 0.05,
              f"magnetic pendulum basin map: hybrid_leapfrog differs in {hybrid}, the reference "
              f"against h/2 in {mp['ref_diff']:.3f}")

        for name in ("workprecision_damped_oscillator.png", "workprecision_double_well.png",
                     "basin_accuracy.png", "basin_accuracy_magnetic_pendulum.png"):
            path = out / name
            ok = path.is_file() and min(matplotlib.image.imread(path).shape[:2]) > 300
            check(failures, ok, f"{name} written, a real image")

    if failures:
        print(f"\n{len(failures)} check(s) failed")
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
