#!/usr/bin/python3
"""The basins of the damped double well from Python, drawn into basins.png.
From a checkout: PYTHONPATH=build/python examples/quickstart.py  (docs/python.md)"""
import os

import matplotlib

if not os.environ.get("DISPLAY"):
    matplotlib.use("Agg")  # no display: draw into the file only
import matplotlib.pyplot as plt

import contactsweep

spec = {"scene": {"name": "double_well", "gamma": 0.1},
        "integrator": {"h": 0.01, "t_end": 100.0},
        "grid": {"q_0": {"from": -3.0, "to": 3.0, "n": 256},
                 "p_0": {"from": -3.0, "to": 3.0, "n": 256}},
        "measures": {"basin": {}}}
ds = contactsweep.run(spec)
ds.basin.plot(x="q_0", y="p_0", cmap="coolwarm")
plt.title("damped double well: which well each (q0, p0) ends in")
# Opened without following a link someone else may have left at the name (a shared directory).
out = os.open("basins.png", os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o666)
with os.fdopen(out, "wb") as png:
    plt.savefig(png, format="png", dpi=120)
