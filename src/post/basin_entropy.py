#!/usr/bin/python3
"""Basin entropy S_b and boundary basin entropy S_bb (Daza, Wagemakers, Georgeot, Guéry-Odelin,
Sanjuán, "Basin entropy: a new tool to analyze uncertainty in dynamical systems", Sci. Rep. 6,
31416, 2016).

The map is cut into non-overlapping boxes of eps x eps cells (cells that do not fill a whole box
at the far edges are dropped). In box i, with p_ij the fraction of its cells carrying label j,
S_i = -sum_j p_ij ln p_ij. S_b is the mean of S_i over all boxes, S_bb the mean over the boxes
that hold more than one label (boundary boxes). S_bb > ln 2 is a sufficient (not necessary)
condition for a fractal boundary (the "log 2 criterion"); with only two labels S_i <= ln 2, so the
criterion can only hold where three or more outcomes (e.g. undecided cells) meet.

Every distinct value is a label: for contactsweep's `basin` map, 0 (undecided or failed) counts as
an outcome of its own, as Daza et al. treat escapes.
"""
import math
from typing import NamedTuple

import numpy as np


class BasinEntropy(NamedTuple):
    S_b: float
    S_bb: float  # NaN when no box holds two labels
    n_boxes: int
    n_boundary_boxes: int

    @property
    def fractal_by_log2(self) -> bool:
        return bool(self.S_bb > math.log(2))


def basin_entropy(labels, eps: int = 5) -> BasinEntropy:
    """S_b and S_bb of a 2-D label map with boxes of eps x eps cells."""
    a = np.asarray(labels)
    if a.ndim != 2:
        raise ValueError(f"need a 2-D label map, got shape {a.shape}")
    nx, ny = a.shape[0] // eps, a.shape[1] // eps
    if nx == 0 or ny == 0:
        raise ValueError(f"map {a.shape} is smaller than one {eps}x{eps} box")
    boxes = a[: nx * eps, : ny * eps].reshape(nx, eps, ny, eps).swapaxes(1, 2).reshape(nx * ny, -1)
    counts = np.stack([(boxes == u).sum(axis=1) for u in np.unique(boxes)], axis=1)
    p = counts / boxes.shape[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        S = -np.where(p > 0, p * np.log(p), 0.0).sum(axis=1)
    boundary = (counts > 0).sum(axis=1) > 1
    S_bb = float(S[boundary].mean()) if boundary.any() else math.nan
    return BasinEntropy(float(S.mean()), S_bb, len(S), int(boundary.sum()))


def _H(p):
    """Shannon entropy (nats) of a probability vector, 0 ln 0 = 0."""
    return -sum(x * math.log(x) for x in p if x > 0)


def expected_random_box_entropy(n_labels: int, cells: int):
    """Mean and standard deviation of S_i for a box of `cells` cells whose labels are i.i.d.
    uniform over n_labels (2 or 3): an exact sum over the multinomial distribution. It is below
    ln(n_labels) because a finite box rarely holds the labels in exactly equal shares."""
    terms = []
    if n_labels == 2:
        for k in range(cells + 1):
            w = math.comb(cells, k) / 2**cells
            terms.append((w, _H([k / cells, 1 - k / cells])))
    elif n_labels == 3:
        for k1 in range(cells + 1):
            for k2 in range(cells - k1 + 1):
                k3 = cells - k1 - k2
                w = math.factorial(cells) / (math.factorial(k1) * math.factorial(k2) *
                                             math.factorial(k3)) / 3**cells
                terms.append((w, _H([k1 / cells, k2 / cells, k3 / cells])))
    else:
        raise ValueError("n_labels must be 2 or 3")
    mean = sum(w * h for w, h in terms)
    var = sum(w * (h - mean) ** 2 for w, h in terms)
    return mean, math.sqrt(var)


def self_check(verbose: bool = True) -> None:
    """Synthetic maps with values known in closed form; raises AssertionError on a mismatch."""
    eps = 5
    ln2 = math.log(2)

    # One basin everywhere: every box has entropy 0 and none is a boundary box.
    r = basin_entropy(np.ones((50, 50), dtype=np.int8), eps)
    assert r.S_b == 0.0 and math.isnan(r.S_bb) and r.n_boundary_boxes == 0, r

    # Half-plane, straight boundary between columns 21 and 22 of a 50 x 50 map (boxes 10 x 10).
    # Only box column 4 (cells 20..24) is cut: 2 of its 5 columns are -1, 3 are +1, so every
    # boundary box has p = (2/5, 3/5) and S_bb = -(0.4 ln 0.4 + 0.6 ln 0.6) = 0.673012 < ln 2
    # (a smooth boundary fails the log 2 criterion, as it must). 10 of the 100 boxes are boundary
    # boxes, so S_b = S_bb / 10.
    half = np.where(np.arange(50)[None, :] < 22, -1, 1) * np.ones((50, 1), dtype=np.int8)
    r = basin_entropy(half, eps)
    s = _H([0.4, 0.6])
    assert r.n_boxes == 100 and r.n_boundary_boxes == 10, r
    assert math.isclose(r.S_bb, s, rel_tol=1e-12) and math.isclose(r.S_b, s / 10, rel_tol=1e-12), r
    assert not r.fractal_by_log2
    # A boundary on a box edge cuts no box: S_b = 0, no boundary boxes.
    r = basin_entropy(np.where(np.arange(50)[None, :] < 25, -1, 1) * np.ones((50, 1)), eps)
    assert r.S_b == 0.0 and r.n_boundary_boxes == 0, r

    # Random maps: N boxes of 25 i.i.d. uniform labels. S_b is a mean of N independent S_i, so it
    # lies within 5 standard errors (sd/sqrt(N)) of the exact expectation, except with
    # probability ~6e-7. Two labels: E[S_i] = 0.6727 (below ln 2 = 0.6931 by the finite-box bias,
    # about 1/(2*25)); a box with a single label has probability 2^-24, so S_bb = S_b in practice.
    # Three labels: E[S_i] = 1.0574 > ln 2, so the log 2 criterion holds.
    rng = np.random.default_rng(12345)
    for n_labels, values in ((2, [-1, 1]), (3, [-1, 0, 1])):
        m = rng.choice(np.array(values, dtype=np.int8), size=(500, 500))
        r = basin_entropy(m, eps)
        mean, sd = expected_random_box_entropy(n_labels, eps * eps)
        tol = 5 * sd / math.sqrt(r.n_boxes)
        assert abs(r.S_b - mean) < tol, (n_labels, r, mean, tol)
        assert abs(r.S_bb - mean) < tol, (n_labels, r, mean, tol)
        assert r.fractal_by_log2 == (n_labels == 3), r
        if verbose:
            print(f"random {n_labels} labels: S_b = {r.S_b:.5f}, expected {mean:.5f} ± {tol:.5f}"
                  f" (ln {n_labels} = {math.log(n_labels):.5f})")
    if verbose:
        print(f"half-plane: S_bb = {s:.6f} (ln 2 = {ln2:.6f}), S_b = {s / 10:.6f}")
        print("basin_entropy self-check passed")


if __name__ == "__main__":
    self_check()
