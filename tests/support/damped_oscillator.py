"""The damped linear oscillator K = p^2/2 + w^2 q^2/2 - gamma z (scene damped_oscillator) in
closed form: its flow on (q, p) is linear, so the exact flow and rk4's step are 2x2 matrices."""
import numpy as np


def generator(omega, gamma):
    """A of (q, p)' = A (q, p): q' = p, p' = -w^2 q + p K_z, K_z = -gamma."""
    return np.array([[0.0, 1.0], [-omega**2, -gamma]])


def expm(a):
    """e^a for a diagonalisable a: the exact flow over t is expm(A t)."""
    w, v = np.linalg.eig(a)
    return (v @ np.diag(np.exp(w)) @ np.linalg.inv(v)).real


def rk4_step(a, h):
    """rk4's step on the linear field A: the Taylor polynomial of degree 4 of hA."""
    ha = h * a
    return np.eye(2) + ha + ha @ ha / 2 + ha @ ha @ ha / 6 + ha @ ha @ ha @ ha / 24


def spec(omega, gamma, method, h, t_end, grid, measures):
    """A spec of scene damped_oscillator, its [grid] and [measures] given as TOML lines."""
    return f"""[scene]
name = "damped_oscillator"
omega = {omega}
gamma = {gamma}
[integrator]
method = "{method}"
h = {h}
t_end = {t_end}
[grid]
{grid}
[measures]
{measures}
"""
