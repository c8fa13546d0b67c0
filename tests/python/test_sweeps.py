"""contactsweep.run of every spec in sweeps/, shrunk as .ci/smoke-sweeps shrinks it, equals the
CLI's file for the same spec: the file run() writes (output=) bit for bit, and the Dataset it
returns, dataset by dataset and attribute by attribute. Specs with a K compile their kernel
twice (the CLI's and the module's cache keys differ by build-id): those are `slow`."""
import pathlib
import tomllib

import pytest

import contactsweep
from compare_outputs import compare
from conftest import ROOT, assert_dataset_is_file, cli_run
from shrink_spec import shrink_overrides

SPECS = sorted((ROOT / "sweeps").glob("*.toml"))


def has_k(path):
    with open(path, "rb") as f:
        return "K" in tomllib.load(f).get("scene", {})


@pytest.mark.parametrize(
    "spec", [pytest.param(s, id=s.stem, marks=[pytest.mark.slow] if has_k(s) else []) for s in SPECS])
def test_run_equals_the_cli(spec, tmp_path):
    overrides = shrink_overrides(spec)
    cli = cli_run(spec, tmp_path / "cli.h5", overrides)
    assert cli.returncode == 0, cli.stderr
    # The overrides as `set`: str values are the command line's text after '='.
    ds = contactsweep.run(pathlib.Path(spec), set=dict(o.split("=", 1) for o in overrides),
                          threads=2, output=tmp_path / "module.h5", progress=False)
    assert compare(tmp_path / "cli.h5", tmp_path / "module.h5") is None
    assert_dataset_is_file(ds, tmp_path / "cli.h5")
    assert ds.attrs["omp_threads"] == 2 and ds.attrs["mpi_ranks"] == 1
    assert ds.attrs["history"].startswith("contactsweep.run(")


def test_sweeps_are_all_here():
    # The parametrisation above is only as good as the glob: a moved folder would test nothing.
    assert len(SPECS) >= 19
