#!/usr/bin/env python3
"""The reference largest Lyapunov exponent of the chaotic forced double-well Duffing oscillator
q'' + delta q' - q + q^3 = F cos(Omega t), delta = 0.3, F = 0.5, Omega = 1.2, computed with an
integrator independent of contactsweep: scipy's DOP853 (rtol 1e-11, atol 1e-12) on the flow and
its variational equations, the tangent renormalised every 10 time units (Benettin et al. 1980).

Each of several trajectories (from rest at q0 in QS) drops a transient of 200 time units and then
averages over T_REF; the mean over trajectories is the reference and the spread of the per-
trajectory values estimates the finite-time fluctuation. tests/test_lyapunov.py stores the output.
Run: /usr/bin/python3 tests/reference/duffing_lyapunov.py   (a few minutes)
"""
import numpy as np
from scipy.integrate import solve_ivp

DELTA, F, OMEGA = 0.3, 0.5, 1.2
QS = [-0.9, -0.6, -0.3, -0.1, 0.1, 0.3, 0.6, 0.9]
TRANSIENT, T_REF, SEGMENT = 200.0, 10000.0, 10.0


def rhs(t, y):
    q, p, dq, dp = y
    force = q - q**3 - DELTA * p + F * np.cos(OMEGA * t)
    return [p, force, dp, (1.0 - 3.0 * q * q) * dq - DELTA * dp]


def exponent(q0):
    y = np.array([q0, 0.0, 1.0, 1.0]) / np.array([1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0)])
    t, total = 0.0, 0.0
    while t < TRANSIENT + T_REF - 1e-9:
        sol = solve_ivp(rhs, (t, t + SEGMENT), y, method="DOP853", rtol=1e-11, atol=1e-12)
        y = sol.y[:, -1]
        t += SEGMENT
        norm = np.hypot(y[2], y[3])
        if t > TRANSIENT + 1e-9:
            total += np.log(norm)
        y[2:] /= norm
    return total / T_REF


if __name__ == "__main__":
    values = [exponent(q0) for q0 in QS]
    print("per trajectory:", " ".join(f"{v:.5f}" for v in values))
    print(f"mean {np.mean(values):.5f}  std {np.std(values, ddof=1):.5f}  (T = {T_REF})")
