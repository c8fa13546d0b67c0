"""The chaotic forced Duffing of the Lyapunov tests, q'' + delta q' - q + q^3 = F cos(Omega t)
with delta = 0.3, F = 0.5, Omega = 1.2, written as K, and its reference exponent:
tests/reference/duffing_lyapunov.py (scipy DOP853, rtol 1e-11, with the variational equations),
8 trajectories from rest, transient 200 dropped, T = 10^4 each: mean and standard deviation."""

SCENE = """[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"
delta = 0.3
F = 0.5
Omega = 1.2
"""
REFERENCE, REFERENCE_STD, REFERENCE_T, REFERENCE_N = 0.10514, 0.0062, 1e4, 8
