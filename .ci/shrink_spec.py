"""--set overrides that shrink a spec: every grid axis given by {from, to, n} gets n = 4; t_end is
capped at t_start + 2 (a whole number of steps) unless the spec measures sync, whose window
must stay inside [0, t_end]. A grid axis
over the step size h must divide t_end into whole steps, so it is replaced whole by two step
sizes near the spec's first and last, t / k for whole k (rounded up, so never above the spec's
own), and t_end is raised to the spec's largest h if that exceeds the cap; integrator.h, which
must divide t_end as well, becomes the first of the two.

    shrink_spec.py SPEC    prints the arguments, one a line ("--set", "KEY=VALUE", ...)
"""
import math
import sys
import tomllib


def shrink_overrides(path):
    """The --set arguments (KEY=VALUE strings, without "--set") that shrink the spec at path."""
    out = []
    with open(path, "rb") as f:
        spec = tomllib.load(f)
    grid = spec.get("grid", {})
    for axis, v in grid.items():
        if axis != "h" and isinstance(v, dict) and "n" in v:
            out.append(f"grid.{axis}.n=4")
    integrator = spec.get("integrator", {})
    t_start = float(integrator.get("t_start", 0.0))
    t_end = float(integrator.get("t_end", t_start + 2.0))
    t = t_end if "sync" in spec.get("measures", {}) else min(t_end, t_start + 2.0)
    if t != t_end and "h" in integrator:  # t_end - t_start stays a whole number of steps
        h = float(integrator["h"])
        t = t_start + h * max(1, round((t - t_start) / h))
    h_axis = grid.get("h")
    if isinstance(h_axis, dict):
        if "values" in h_axis:
            hs = [float(x) for x in h_axis["values"]]
        else:
            n = int(h_axis["n"])
            lo, hi = float(h_axis["from"]), float(h_axis["to"])
            hs = [lo + (hi - lo) * i / max(n - 1, 1) for i in range(n)]
        t = min(max(t, max(hs)), t_end)
        picked = []
        for h in (hs[0], hs[-1]):
            value = t / max(1, math.ceil(t / h - 1e-9))
            if value not in picked:
                picked.append(value)
        out.append(f"grid.h={{ values = [{', '.join(repr(x) for x in picked)}] }}")
        out.append(f"integrator.h={picked[0]!r}")  # checked against t_end too
    if "sync" not in spec.get("measures", {}) or t != t_end:
        out.append(f"integrator.t_end={t!r}")
    if "observe_window" in spec.get("measures", {}) and t != t_end:  # kept inside the shorter run
        out.append(f"measures.observe_window={{ from = {t_start!r}, to = {t!r} }}")
    return out


if __name__ == "__main__":
    for override in shrink_overrides(sys.argv[1]):
        print(f"--set\n{override}")
