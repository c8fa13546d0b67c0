#!/usr/bin/python3
"""Checks that a contactsweep result file reads as netCDF-4 through xarray's h5netcdf engine.

    test_xarray_open.py FILE.h5 [--dims NAME=LEN ...] [--vars NAME ...] [--root-attrs NAME ...]

Generic checks, for any contactsweep output:
  * opens with engine="h5netcdf" while the netCDF4 module is hidden (it must not be needed),
    without warnings from the decoders;
  * every dimension has a float64 coordinate of the same name (not decoded to times);
  * every data variable has the dims (axes...) or (axes..., t), the same axes for all, t last,
    but for the attractor table of a basin map (dims over `attractor` and the axes);
  * every variable has a str long_name; no attribute anywhere comes back as bytes;
  * flag_values and _FillValue have the variable's own stored dtype, and flag_meanings has one
    word per flag value;
  * every value can be read.
--dims gives the exact, ordered dimensions (t last if present); --vars the exact set of data
variables; --root-attrs root attributes that must be present.
Exits 1 with one line per problem.
"""
import argparse
import sys
import warnings

# Simulate a machine without netCDF4-python: the h5netcdf engine must not depend on it.
sys.modules["netCDF4"] = None

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

TIME = "t"


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("path")
    parser.add_argument("--dims", nargs="*", default=None, metavar="NAME=LEN")
    parser.add_argument("--vars", nargs="*", default=None, metavar="NAME")
    parser.add_argument("--root-attrs", nargs="*", default=[], metavar="NAME")
    return parser.parse_args()


def open_strict(path, **kwargs):
    """Opens with every warning turned into an error: a decoder that complains is a bug."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return xr.open_dataset(path, engine="h5netcdf", **kwargs)


def bytes_attributes(owner, attrs):
    return [
        f"{owner}: attribute {key!r} is bytes, not str"
        for key, value in attrs.items()
        if isinstance(value, (bytes, np.bytes_))
    ]


def check_coordinates(ds):
    problems = []
    for dim in ds.dims:
        if dim not in ds.coords:
            problems.append(f"dimension {dim!r} has no coordinate")
            continue
        coord = ds[dim]
        if coord.dims != (dim,):
            problems.append(f"coordinate {dim!r} has dims {coord.dims}, not ({dim!r},)")
        if coord.dtype != np.float64:
            problems.append(f"coordinate {dim!r} has dtype {coord.dtype}, not float64")
        if dim not in ds.indexes:
            problems.append(f"coordinate {dim!r} is not an index")
    return problems


def expected_axes(ds, wanted_dims):  # TABLES: defined below, read at call time
    if wanted_dims is not None:
        return tuple(d for d, _ in wanted_dims if d != TIME and d not in TABLES)
    # The longest dims tuple of the data variables, without t.
    dims = [tuple(d for d in v.dims if d != TIME) for v in ds.data_vars.values()]
    return max(dims, key=len, default=())


# The attractor table of a basin map (its samples along each attractor too), and its fractions
# along one axis (a continuation).
TABLES = {"attractor", "point", "var"}  # attractor_points: (attractor, point, var)


def check_data_variables(ds, axes):
    problems = []
    for name, var in ds.data_vars.items():
        per_value = name in ("basin_undecided_fraction", "basin_entropy", "boundary_basin_entropy",
                             "uncertainty_exponent", "wada_merging_fraction")  # along a continuation's axis
        is_table = set(var.dims) & TABLES or per_value
        if is_table and set(var.dims) <= set(axes) | TABLES:
            continue
        if var.dims not in (axes, axes + (TIME,)):
            problems.append(f"{name!r} has dims {var.dims}, expected {axes} or {axes + (TIME,)}")
    return problems


def check_attributes(ds, raw):
    problems = bytes_attributes("root", ds.attrs)
    for name, var in ds.variables.items():
        problems += bytes_attributes(repr(name), var.attrs)
        long_name = var.attrs.get("long_name")
        if not isinstance(long_name, str) or not long_name:
            problems.append(f"{name!r} has no str long_name (got {long_name!r})")
        if "units" in var.attrs and not isinstance(var.attrs["units"], str):
            problems.append(f"{name!r}: units is not a str")

    # Stored dtypes and _FillValue are only visible without CF decoding.
    for name, var in raw.variables.items():
        problems += bytes_attributes(repr(name), var.attrs)
        for key in ("flag_values", "_FillValue"):
            if key in var.attrs:
                dtype = np.asarray(var.attrs[key]).dtype
                if dtype != var.dtype:
                    problems.append(f"{name!r}: {key} has dtype {dtype}, variable has {var.dtype}")
        if "flag_values" in var.attrs:
            count = np.atleast_1d(var.attrs["flag_values"]).size
            meanings = var.attrs.get("flag_meanings")
            if not isinstance(meanings, str) or len(meanings.split()) != count:
                problems.append(f"{name!r}: flag_meanings {meanings!r} does not name {count} flags")
    return problems


def check_expectations(ds, args):
    problems = []
    if args.dims is not None:
        wanted = {d: int(n) for d, n in args.dims}
        if dict(ds.sizes) != wanted:
            problems.append(f"dims are {dict(ds.sizes)}, expected {wanted}")
    if args.vars is not None and set(ds.data_vars) != set(args.vars):
        problems.append(f"data variables are {sorted(ds.data_vars)}, expected {sorted(args.vars)}")
    for key in args.root_attrs:
        if key not in ds.attrs:
            problems.append(f"root attribute {key!r} is missing")
    return problems


def main():
    args = parse_args()
    if args.dims is not None:
        args.dims = [(d.split("=")[0], d.split("=")[1]) for d in args.dims]
    try:
        ds = open_strict(args.path)
        raw = open_strict(args.path, decode_cf=False)
        ds.load()
    except Exception as error:  # any failure to open or decode is the finding
        print(f"{args.path}: cannot open with engine='h5netcdf': {type(error).__name__}: {error}")
        return 1
    if sys.modules.get("netCDF4") is not None:
        print(f"{args.path}: netCDF4 was imported")
        return 1

    problems = check_coordinates(ds)
    problems += check_data_variables(ds, expected_axes(ds, args.dims))
    problems += check_attributes(ds, raw)
    problems += check_expectations(ds, args)
    for problem in problems:
        print(f"{args.path}: {problem}")
    if not problems:
        print(f"{args.path}: OK, dims {dict(ds.sizes)}, {len(ds.data_vars)} data variables")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
