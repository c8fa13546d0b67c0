"""Shared by the Python module's tests: the CLI to compare with, and file-against-dataset checks.

CTest sets PYTHONPATH to build/python and CONTACTSWEEP to the program (tests/CMakeLists.txt);
from a checkout, `PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python` works too.
"""
import os
import pathlib
import subprocess
import sys

import h5py
import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = os.environ.get("CONTACTSWEEP", str(ROOT / "build" / "contactsweep"))
sys.path.insert(0, str(ROOT / "tests"))  # compare_outputs.py
sys.path.insert(0, str(ROOT / ".ci"))  # shrink_spec.py, as .ci/smoke-sweeps shrinks

# Attributes that say how a run was made, not what it computed (compare_outputs.py).
RUN_ATTRIBUTES = {"history", "mpi_ranks", "omp_threads"}
# What netCDF-4 and HDF5 dimension scales keep in attributes: xarray turns them into structure.
STRUCTURE_ATTRIBUTES = {"DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME", "_Netcdf4Dimid",
                        "_Netcdf4Coordinates", "_nc3_strict"}


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: compiles K kernels (CTest: python_module_slow)")


def cli_run(spec, output, overrides=(), cwd=None):
    """`contactsweep run` as a user types it; returns the completed process."""
    args = [CLI, "run", str(spec), "-o", str(output), "--quiet"]
    for override in overrides:
        args += ["--set", override]
    return subprocess.run(args, cwd=cwd, capture_output=True, text=True, stdin=subprocess.DEVNULL)


def plain(value):
    """An attribute as comparable data: text as str, numbers as (dtype, bytes)."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode()
    if isinstance(value, str):
        return value
    array = np.asarray(value)
    if array.dtype.kind in "OSU":
        return [plain(v) for v in array.ravel()]
    return (array.dtype.str, array.shape if array.ndim else (), array.tobytes())


def assert_dataset_is_file(ds, path):
    """Every dataset of the file is a variable of ds with the same dtype, shape and bits, and
    the same attributes; ds has nothing else; root attributes equal but for RUN_ATTRIBUTES."""
    with h5py.File(path, "r") as f:
        names = [name for name, obj in f.items() if isinstance(obj, h5py.Dataset)]
        assert sorted(names) == sorted(ds.variables), "the variables are not the file's datasets"
        for name in names:
            stored, got = f[name][()], ds[name].values
            assert got.dtype == stored.dtype and got.shape == stored.shape, name
            assert got.tobytes() == stored.tobytes(), f"{name}: values differ"
            want = {k: plain(v) for k, v in f[name].attrs.items() if k not in STRUCTURE_ATTRIBUTES}
            have = {k: plain(v) for k, v in ds[name].attrs.items()}
            assert have == want, f"{name}: attributes differ"
        want = {k: plain(v) for k, v in f.attrs.items() if k not in RUN_ATTRIBUTES | STRUCTURE_ATTRIBUTES}
        have = {k: plain(v) for k, v in ds.attrs.items() if k not in RUN_ATTRIBUTES}
        assert have == want, "root attributes differ"


@pytest.fixture
def private_tmpdir(tmp_path, monkeypatch):
    """The temporary directory moved to tmp_path/tmp, so that a test sees what run() leaves there."""
    import tempfile

    directory = tmp_path / "tmp"
    directory.mkdir()
    monkeypatch.setenv("TMPDIR", str(directory))  # run() then uses tempfile's directory ...
    monkeypatch.setattr(tempfile, "tempdir", str(directory))  # ... which tempfile caches
    return directory
