#!/usr/bin/python3
"""Asserts that contactsweep output files hold the same bits in every dataset.

Usage: compare_outputs.py REFERENCE OTHER...   (exit 1 naming the first difference)
Root attributes that describe how a run was made (history, ranks, threads) may differ;
everything else, data and attributes, must be identical.
"""
import sys

import h5py
import numpy as np

RUN_ATTRIBUTES = {"history", "mpi_ranks", "omp_threads"}


def datasets(f):
    names = []
    f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return sorted(names)


def same_bits(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def compare(ref_path, other_path):
    with h5py.File(ref_path, "r") as ref, h5py.File(other_path, "r") as other:
        if datasets(ref) != datasets(other):
            return f"dataset lists differ: {datasets(ref)} vs {datasets(other)}"
        for name in datasets(ref):
            if not same_bits(ref[name][()], other[name][()]):
                a, b = np.asarray(ref[name][()]), np.asarray(other[name][()])
                return f"dataset {name} differs ({np.count_nonzero(a != b)} elements)"
        for key in set(ref.attrs) | set(other.attrs):
            if key in RUN_ATTRIBUTES:
                continue
            if key not in ref.attrs or key not in other.attrs:
                return f"root attribute {key} is in only one file"
            # Bits, not ==: a run over several step sizes writes h = NaN, which == calls unequal.
            a, b = np.asarray(ref.attrs[key]), np.asarray(other.attrs[key])
            same = same_bits(a, b) if a.dtype.kind in "fiub" else np.array_equal(a, b)
            if not same:
                return f"root attribute {key} differs"
    return None


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    failures = 0
    for other in sys.argv[2:]:
        problem = compare(sys.argv[1], other)
        print(f"{other}: {'identical to ' + sys.argv[1] if problem is None else problem}")
        failures += problem is not None
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
