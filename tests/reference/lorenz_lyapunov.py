#!/usr/bin/env python3
"""The finite-time largest Lyapunov exponent of the Lorenz system (s = 10, r = 28, b = 8/3) over
windows of W = 1000 time units, computed with an integrator independent of contactsweep: scipy's
DOP853 (rtol 1e-10, atol 1e-10) on the flow and its variational equations, the tangent
renormalised every time unit (Benettin et al. 1980).

Each trajectory starts at (x0, 1, 25), drops a transient of 100 time units (the tangent aligns
within a few units) and averages over W. The mean over trajectories estimates lambda_1 (the
literature's 0.9056, Sprott 2003). Twelve DOP853 trajectories are too few for the spread of the
finite-time values, which sets the tolerance of tests/test_showcases.py: that comes from 256
trajectories of the classical RK4 in numpy, h = 0.005, all lanes at once (independent of
contactsweep too; its own error in lambda_1 is O(h^4), ~10^-9 here).

Output (Debian 12's scipy 1.10, numpy 1.24):
  DOP853, 12 trajectories:  mean 0.90757  std 0.00344  (W = 1000)
  RK4,   256 trajectories:  mean 0.90587  std 0.00488  (W = 1000)
Run: /usr/bin/python3 tests/reference/lorenz_lyapunov.py [dop853|rk4]   (~6 min and ~30 s)
"""
import sys

import numpy as np
from scipy.integrate import solve_ivp

S, R, B = 10.0, 28.0, 8.0 / 3.0
X0 = [-15.0, -10.0, -6.0, -3.0, -1.0, 1.0, 3.0, 6.0, 10.0, 15.0, 7.5, -7.5]
TRANSIENT, WINDOW, SEGMENT = 100.0, 1000.0, 1.0


def rhs(t, y):
    x, v, z = y[:3]
    d = y[3:]
    jac = np.array([[-S, S, 0.0], [R - z, -1.0, -x], [v, x, -B]])
    return np.concatenate([[S * (v - x), x * (R - z) - v, x * v - B * z], jac @ d])


def exponent(x0):
    y = np.array([x0, 1.0, 25.0, 1.0, 1.0, 1.0])
    y[3:] /= np.linalg.norm(y[3:])
    t, total = 0.0, 0.0
    while t < TRANSIENT + WINDOW - 1e-9:
        sol = solve_ivp(rhs, (t, t + SEGMENT), y, method="DOP853", rtol=1e-10, atol=1e-10)
        y = sol.y[:, -1]
        t += SEGMENT
        norm = np.linalg.norm(y[3:])
        if t > TRANSIENT + 1e-9:
            total += np.log(norm)
        y[3:] /= norm
    return total / WINDOW


def rk4_spread(n=256, h=0.005):
    """n trajectories at once, starts spread over x0 in [-20, 20], y0 in [-25, 25], z0 = 25."""
    def f(y):
        x, v, z, dx, dv, dz = y
        return np.array([S * (v - x), x * (R - z) - v, x * v - B * z,
                         S * (dv - dx), (R - z) * dx - dv - x * dz, v * dx + x * dv - B * dz])

    def step(y):
        k1 = f(y)
        k2 = f(y + h / 2 * k1)
        k3 = f(y + h / 2 * k2)
        k4 = f(y + h * k3)
        return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

    y = np.zeros((6, n))
    y[0], y[1], y[2] = np.linspace(-20, 20, n), np.linspace(25, -25, n), 25.0
    y[3:] = 1 / np.sqrt(3.0)
    total = np.zeros(n)
    for i in range(int(round((TRANSIENT + WINDOW) / h))):
        y = step(y)
        if i % 20 == 19:
            norm = np.linalg.norm(y[3:], axis=0)
            if i >= int(round(TRANSIENT / h)):
                total += np.log(norm)
            y[3:] /= norm
    return total / WINDOW


if __name__ == "__main__":
    which = sys.argv[1] if len(sys.argv) > 1 else "both"
    if which in ("dop853", "both"):
        values = [exponent(x0) for x0 in X0]
        print("per trajectory:", " ".join(f"{v:.5f}" for v in values))
        print(f"DOP853, {len(values)} trajectories: mean {np.mean(values):.5f}  "
              f"std {np.std(values, ddof=1):.5f}  (W = {WINDOW})")
    if which in ("rk4", "both"):
        values = rk4_spread()
        print(f"RK4, {len(values)} trajectories: mean {np.mean(values):.5f}  "
              f"std {np.std(values, ddof=1):.5f}  (W = {WINDOW})")
