#!/usr/bin/python3
"""Asserts that contactsweep output files hold the same bits in every dataset.

Usage: compare_outputs.py REFERENCE OTHER...   (exit 1 naming the first difference)
Root attributes that describe how a run was made (history, ranks, threads) may differ;
everything else must be identical: the groups and datasets, every dataset's data, and the
attributes of the root, of every group and of every dataset (references compared by the names
they point to).
"""
import sys

import h5py
import numpy as np

RUN_ATTRIBUTES = {"history", "mpi_ranks", "omp_threads"}


def objects(f):
    names = []
    f.visit(names.append)
    return sorted(names)


def datasets(f):
    return [name for name in objects(f) if isinstance(f[name], h5py.Dataset)]


def same_bits(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def comparable(f, value):
    """An attribute's value with object references (dimension scales' DIMENSION_LIST and
    REFERENCE_LIST) replaced by the names they point to, which are what two files can share."""
    if isinstance(value, h5py.Reference):
        return f[value].name if value else None
    if isinstance(value, np.void):  # a compound element (REFERENCE_LIST: reference, index)
        return tuple(comparable(f, value[k]) for k in value.dtype.names)
    if isinstance(value, np.ndarray) and value.dtype.kind in "OV":
        return [comparable(f, v) for v in value]
    if isinstance(value, (list, tuple)):
        return [comparable(f, v) for v in value]
    return value


def same_attribute(ref, other, a, b):
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray) or np.isscalar(a):
        a, b = np.asarray(a), np.asarray(b)
        if a.dtype.kind in "fiub" or b.dtype.kind in "fiub":
            # Bits, not ==: a run over several step sizes writes h = NaN, which == calls unequal.
            return same_bits(a, b)
        if a.dtype.kind in "OV" or b.dtype.kind in "OV":
            return comparable(ref, a) == comparable(other, b)
        return a.dtype == b.dtype and np.array_equal(a, b)
    return comparable(ref, a) == comparable(other, b)


def compare_attributes(ref, other, name, ignore=()):
    a, b = ref[name].attrs, other[name].attrs
    for key in sorted(set(a) | set(b)):
        if key in ignore:
            continue
        if key not in a or key not in b:
            return f"attribute {key} of {name} is in only one file"
        if not same_attribute(ref, other, a[key], b[key]):
            return (f"attribute {key} of {name} differs: {comparable(ref, a[key])!r} vs "
                    f"{comparable(other, b[key])!r}")
    return None


def compare(ref_path, other_path):
    with h5py.File(ref_path, "r") as ref, h5py.File(other_path, "r") as other:
        if objects(ref) != objects(other):
            return f"object lists differ: {objects(ref)} vs {objects(other)}"
        for name in datasets(ref):
            if not same_bits(ref[name][()], other[name][()]):
                a, b = np.asarray(ref[name][()]), np.asarray(other[name][()])
                return f"dataset {name} differs ({np.count_nonzero(a != b)} elements)"
        problem = compare_attributes(ref, other, "/", ignore=RUN_ATTRIBUTES)
        for name in objects(ref):
            problem = problem or compare_attributes(ref, other, name)
        return problem


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
