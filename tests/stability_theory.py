#!/usr/bin/python3
"""Linear stability limits on scene A, derived independently of contactsweep's code (numpy only).

Scene A, K = (p² + ω²q²)/2 − γz, moves (q, p) by the linear ODE x' = A x, A = [[0, 1], [−ω², −γ]]
(q' = K_p = p, p' = −K_q + p·K_z = −ω²q − γp); z and λ never feed back. So every method's step
is a 2×2 matrix M(h), written here from the published schemes, not from our headers:

* RK4: M = R(hA), R(z) = 1 + z + z²/2 + z³/6 + z⁴/24, its stability polynomial. The eigenvalues
  of M are R(hμ) for the eigenvalues μ of A, so the limit is the smallest h > 0 with
  |R(hμ)|² = 1, a polynomial of degree 8 in h solved with numpy (2√2 at γ = 0, where μ = ±iω).
* Contact splittings (Bravetti, Seri, Vermeeren, Zadra 2020): exact flows of p²/2
  ([[1, t], [0, 1]]), of V = ω²q²/2 ([[1, 0], [−ω²t, 1]]) and of −γz (p ×= e^{−γt}: diag(1,
  e^{−γt})), composed as S₂(τ) = Z(τ/2) V(τ/2) T(τ) V(τ/2) Z(τ/2), then S(h) = Π S₂(w_s h) over
  the triple jump (Yoshida 1990, order 4) and Yoshida's 7-stage solution A (1990, table 1, as
  printed there: order 6).
* Hybrid leap-frog (Sogo & Ohnishi), K_z = −γ: a = 1 + hγ/2, b = 1 − hγ/2,
  p½ = (p − h/2·ω²q)/a, q' = q + h·p½, p' = b·p½ − h/2·ω²q'.
* Symmetric leap-frog (contact variational, Vermeeren, Bravetti, Seri 2019): a = 1 − hγ/2,
  b = 1 + hγ/2, p½ = a·p − h/2·ω²q, q' = q + h·p½, p' = (p½ − h/2·ω²q')/b.

The limit of a matrix method is the first h where the spectral radius exceeds 1: a scan in steps
of 1e-4 (a scan in steps of 1e-5 found the same first limits; the narrowest window before a
first limit is 0.059 wide), then a bisection to 1e-13. "Exceeds" means > 1 + 1e-12: at γ = 0
the symplectic maps have |λ| = 1 up to round-off below their limit.

  stability_theory.py                    print the limits at γ = 0, 0.1 and 0.5 (ω = 1)
  stability_theory.py --header FILE      write the C++ header of the scene-A limits (γ = 0.1)
  stability_theory.py --check FILE POST  exit 1 unless FILE holds what --header writes, and the
                                         4-decimal tables of POST (src/post/stability_maps.py)
                                         and the facts of PHYSICS.md agree with the derivation
"""
import math
import re
import sys
from pathlib import Path

import numpy as np
from numpy.polynomial import polynomial as P

OMEGA = 1.0
GAMMAS = (0.0, 0.1, 0.5)
SCENE_A_GAMMA = 0.1
METHODS = ("hybrid_leapfrog", "symmetric_leapfrog", "contact_splitting2", "contact_splitting4",
           "contact_splitting6", "rk4")


def cpp_name(method):
    """The C++ type of a method: its name in CamelCase, as src/numerics/method_list.cmake derives
    it from the method's file name (contact_splitting4 -> ContactSplitting4)."""
    return "".join(word[:1].upper() + word[1:] for word in method.split("_"))


UNSTABLE = 1.0 + 1e-12

# Composition weights from the literature (palindromic, summing to 1).
_C = 2.0 ** (1.0 / 3.0)
TRIPLE_JUMP = (1.0 / (2.0 - _C), -_C / (2.0 - _C), 1.0 / (2.0 - _C))
_Y1, _Y2, _Y3 = -1.17767998417887, 0.235573213359357, 0.784513610477560  # Yoshida's solution A
YOSHIDA6 = (_Y3, _Y2, _Y1, 1.0 - 2.0 * (_Y1 + _Y2 + _Y3), _Y1, _Y2, _Y3)
WEIGHTS = {"contact_splitting2": (1.0,), "contact_splitting4": TRIPLE_JUMP,
           "contact_splitting6": YOSHIDA6}


def _mat(a, b, c, d):
    """Stacked 2×2 matrices [[a, b], [c, d]] over the leading axis of the arrays."""
    a, b, c, d = np.broadcast_arrays(a, b, c, d)
    return np.stack([np.stack([a, b], -1), np.stack([c, d], -1)], -2)


def strang(tau, gamma):
    one, zero = np.ones_like(tau), np.zeros_like(tau)
    z = _mat(one, zero, zero, np.exp(-gamma * tau / 2))
    v = _mat(one, zero, -OMEGA**2 * tau / 2, one)
    t = _mat(one, tau, zero, one)
    return z @ v @ t @ v @ z


def step_matrix(method, h, gamma):
    h = np.asarray(h, dtype=float)
    one = np.ones_like(h)
    w2 = OMEGA**2
    if method in WEIGHTS:
        m = _mat(one, 0 * h, 0 * h, one)
        for w in WEIGHTS[method]:
            m = strang(w * h, gamma) @ m
        return m
    if method == "rk4":
        a = _mat(0 * h, one, -w2 * one, -gamma * one)
        ha = h[..., None, None] * a
        eye = _mat(one, 0 * h, 0 * h, one)
        m, term = eye.copy(), eye.copy()
        for k in range(1, 5):
            term = term @ ha / k
            m = m + term
        return m
    if method == "hybrid_leapfrog":
        a, b = 1 + h * gamma / 2, 1 - h * gamma / 2
        # p½ = (p − h/2·ω²q)/a; q' = q + h p½; p' = b p½ − h/2 ω² q'
        ph = _mat(-h / 2 * w2 / a, 1 / a, 0 * h, 0 * h)[..., 0, :]  # row: p½ in terms of (q, p)
    elif method == "symmetric_leapfrog":
        a, b = 1 - h * gamma / 2, 1 + h * gamma / 2
        ph = _mat(-h / 2 * w2 * one, a, 0 * h, 0 * h)[..., 0, :]
    else:
        raise ValueError(method)
    qn = np.stack([one, 0 * h], -1) + h[..., None] * ph
    if method == "hybrid_leapfrog":
        pn = b[..., None] * ph - (h / 2 * w2)[..., None] * qn
    else:
        pn = (ph - (h / 2 * w2)[..., None] * qn) / b[..., None]
    return np.stack([qn, pn], -2)


def spectral_radius(method, h, gamma):
    m = step_matrix(method, h, gamma)
    tr, det = m[..., 0, 0] + m[..., 1, 1], m[..., 0, 0] * m[..., 1, 1] - m[..., 0, 1] * m[..., 1, 0]
    root = np.sqrt((tr * tr - 4 * det).astype(complex))
    return np.maximum(np.abs(tr + root), np.abs(tr - root)) / 2


def matrix_limit(method, gamma, scan_step=1e-4, h_max=4.0):
    hs = np.arange(1, int(h_max / scan_step) + 1) * scan_step
    unstable = spectral_radius(method, hs, gamma) > UNSTABLE
    first = int(np.argmax(unstable))
    assert unstable[first], f"{method} stable up to h = {h_max}"
    lo, hi = (hs[first - 1] if first else 0.0), hs[first]
    while hi - lo > 1e-13:
        mid = 0.5 * (lo + hi)
        if spectral_radius(method, np.array([mid]), gamma)[0] > UNSTABLE:
            hi = mid
        else:
            lo = mid
    return lo


def rk4_limit(gamma):
    """Smallest h > 0 with |R(hμ)| = 1, μ = −γ/2 + i√(ω² − γ²/4): roots of a real polynomial."""
    mu = complex(-gamma / 2, math.sqrt(OMEGA**2 - gamma**2 / 4))
    r = np.array([mu**k / math.factorial(k) for k in range(5)])  # R(hμ) in powers of h
    modulus2 = P.polymul(r, np.conj(r)).real  # |R(hμ)|² (conjugate pair: real coefficients)
    modulus2[0] -= 1.0
    roots = P.polyroots(modulus2)
    real = [x.real for x in roots if abs(x.imag) < 1e-9 and x.real > 1e-6]
    return min(real)


def derive():
    limits = {g: {m: matrix_limit(m, g) for m in METHODS} for g in GAMMAS}
    for g in GAMMAS:
        from_polynomial = rk4_limit(g)
        # The two derivations of RK4's limit agree to the bisection and root-finding precision.
        assert abs(from_polynomial - limits[g]["rk4"]) < 1e-9, (g, from_polynomial,
                                                                limits[g]["rk4"])
        limits[g]["rk4"] = from_polynomial
    assert abs(limits[0.0]["rk4"] - 2 * math.sqrt(2)) < 1e-12, limits[0.0]["rk4"]
    return limits


def header(limits):
    lines = [
        "// Generated by tests/stability_theory.py --header (numpy, from the published schemes:",
        "// RK4's stability polynomial, the splittings' composition matrices, the leap-frogs' "
        "steps),",
        "// never from our code. ctest's stability_theory checks that it is up to date.",
        "#pragma once",
        "",
        "namespace cs::test::stability_theory {",
        "",
        f"// Scene A (ω = {OMEGA:g}, γ = {SCENE_A_GAMMA:g}): the first h where the (q, p) "
        "step map's",
        "// spectral radius exceeds 1, to 1e-13.",
    ]
    for m in METHODS:
        lines.append(f"inline constexpr double k{cpp_name(m)} = {limits[SCENE_A_GAMMA][m]!r};")
    lines += ["", "}  // namespace cs::test::stability_theory", ""]
    return "\n".join(lines)


def check(header_path, post_path, limits):
    problems = []
    # The header's values against these, to the bisection's precision (its text may differ in
    # the last digits from one numpy to another).
    text = Path(header_path).read_text()
    written = dict(re.findall(r"constexpr double k(\w+) = ([0-9.e+-]+);", text))
    for m in METHODS:
        value = written.get(cpp_name(m))
        if value is None or abs(float(value) - limits[SCENE_A_GAMMA][m]) > 1e-12:
            problems.append(f"{header_path}: {m} = {value}, derived {limits[SCENE_A_GAMMA][m]!r}: "
                            f"run stability_theory.py --header {header_path}")
    sys.path.insert(0, str(Path(post_path).resolve().parent))
    import stability_maps  # noqa: E402 (src/post: its 4-decimal tables for the charts)

    tables = dict(stability_maps.THEORY_LIMITS)
    tables.setdefault(SCENE_A_GAMMA, stability_maps.THEORY_LIMIT_A)
    for g, table in tables.items():
        for m in METHODS:
            printed = table.get(m)
            # Printed to 4 decimals: within half a unit of the last one.
            if printed is None or abs(printed - limits[g][m]) > 0.5e-4 + 1e-12:
                problems.append(f"{post_path}: gamma = {g}, {m}: {printed}, "
                                f"derived {limits[g][m]:.6f}")
    # PHYSICS.md: hybrid leap-frog on scene A h < 2.000; RK4 h < 2.9 (one decimal).
    scene_a = limits[SCENE_A_GAMMA]
    if abs(scene_a["hybrid_leapfrog"] - 2.0) > 0.5e-3:
        problems.append(f"PHYSICS.md's 2.000 for the hybrid leap-frog: derived "
                        f"{scene_a['hybrid_leapfrog']}")
    if round(scene_a["rk4"], 1) != 2.9:
        problems.append(f"PHYSICS.md's 2.9 for RK4: derived {scene_a['rk4']}")
    for p in problems:
        print("FAIL", p)
    return not problems


def main():
    limits = derive()
    if len(sys.argv) == 3 and sys.argv[1] == "--header":
        Path(sys.argv[2]).write_text(header(limits))
    elif len(sys.argv) == 4 and sys.argv[1] == "--check":
        sys.exit(0 if check(sys.argv[2], sys.argv[3], limits) else 1)
    elif len(sys.argv) == 1:
        for g in GAMMAS:
            print(f"gamma = {g}: " + ", ".join(f"{m} {limits[g][m]:.10f}" for m in METHODS))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
