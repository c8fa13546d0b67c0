#!/usr/bin/python3
"""The basins of the damped double well from Python, drawn into basins.png.
From a checkout: PYTHONPATH=build/python examples/quickstart.py  (docs/python.md)"""
import os
import stat
import sys

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
# In a shared directory someone else may have left something at the name: a link is not followed,
# and their file or FIFO is not written into (nor waited on): refused, naming it.
try:
    out = os.open("basins.png", os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK, 0o666)
except OSError as e:
    sys.exit(f"cannot write basins.png: {e.strerror} (a link or a FIFO is there?); move it away")
found = os.fstat(out)
if not stat.S_ISREG(found.st_mode) or found.st_uid != os.geteuid():
    why = ("it is not a regular file" if not stat.S_ISREG(found.st_mode)
           else f"it belongs to user id {found.st_uid}, not to you")
    sys.exit(f"cannot write basins.png: {why}; move it away")
os.ftruncate(out, 0)
with os.fdopen(out, "wb") as png:
    plt.savefig(png, format="png", dpi=120)
