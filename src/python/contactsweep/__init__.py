"""contactsweep in Python: the engine of `contactsweep run` in this process, results as xarray.

    import contactsweep
    ds = contactsweep.run("sweeps/basins_double_well.toml", set={"grid.q_0.n": 64})
    ds.basin.plot()

run() returns the datasets, values and attributes of the file `contactsweep run` writes for
the same spec, bit for bit (docs/python.md). scenes() and methods() are what `contactsweep
scenes` and `contactsweep methods` list.
"""
import os
import shutil
import tempfile
import threading

from . import _core, _progress, _toml

__all__ = ["run", "scenes", "methods", "__version__"]
__version__ = _core.__version__

# One run at a time in a process: the HDF5 library (Debian's, with MPI) is not thread-safe, and a
# run sets the process's OpenMP thread count. run() called from several threads at once crashed
# the interpreter; each call now waits for the one before it.
_one_run = threading.Lock()


def _run_core(*args):
    with _one_run:
        _core.run(*args)


def scenes():
    """The built-in scenes: a list of dicts (name, paper_label, hamiltonian, dof, z_feeds_back,
    parameters and variables as lists of {name, default, description}, measures, split_parts,
    default_h, default_t_end)."""
    return _core.scenes()


def methods():
    """The integrators: a list of dicts (name, order, force_evaluations_per_step, properties,
    needs_split_parts, adaptive: True for a method with its own step size per lane, rtol/atol)."""
    return _core.methods()


def _spec_source(spec):
    """(source name for messages, TOML text or None, path or '') of a path, TOML text or dict."""
    if isinstance(spec, os.PathLike):
        return os.fspath(spec), None
    if isinstance(spec, str):
        # A spec's text has a newline or a '='; a path has neither (a file name with '=' in it
        # must come as a pathlib.Path).
        if "\n" in spec or "=" in spec:
            return "<spec text>", spec
        return spec, None
    if hasattr(spec, "keys"):
        return "<spec dict>", _toml.dumps(spec)
    raise ValueError(f"spec: expected a path, TOML text or a dict, got {type(spec).__name__}")


def _overrides(set):
    """--set arguments: a str value is the text after '=' as on the command line (a bare word
    is a string); any other value is written as TOML."""
    if set is None:
        return []
    if not hasattr(set, "items"):
        raise ValueError(f"set: expected a dict of dotted keys, got {type(set).__name__}")
    return [f"{k}={v if isinstance(v, str) else _toml.value(v)}" for k, v in set.items()]


def _scratch_roots():
    """Where the private directory of a run without `output` may go, best first. $TMPDIR (or
    TEMP, TMP: what tempfile reads) when set: the user's choice. Else /dev/shm, a tmpfs, where
    the journal's and the file's fsyncs cost nothing (a 128 x 128 basin map: 0.14 s there,
    0.74 s in /tmp on ext4, docs/python.md), then tempfile's default (None)."""
    if any(os.environ.get(name) for name in ("TMPDIR", "TEMP", "TMP")):
        return [None]
    if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK | os.X_OK):
        return ["/dev/shm", None]
    return [None]


def _load(path):
    """The whole file in memory, the file closed. No CF masking or decoding: the values are the
    file's bits and the attributes its attributes (_FillValue stays an attribute)."""
    import xarray

    with xarray.open_dataset(path, engine="h5netcdf", mask_and_scale=False,
                             decode_times=False) as ds:
        return ds.load()


def run(spec, set=None, threads=None, output=None, *, progress=True):
    """Runs `spec` in this process and returns the result as an xarray.Dataset.

    spec: a path, TOML text, or a dict shaped like a spec ({"scene": {...}, "grid": {...}}).
    set: {"integrator.h": 0.005, ...}, as `--set`. threads: OpenMP threads (default: OpenMP's).
    output: also write the file there, as `contactsweep run -o output` (which must not exist).
    progress: True shows a bar (tqdm if it imports, else a line on stderr), False nothing; a
    callable is called with the share done (0 to 1) instead, about every 0.1 s.
    Raises ValueError for bad input (the CLI's message), KeyboardInterrupt on Ctrl-C (nothing
    left under `output`, nor its journal), RuntimeError otherwise.
    """
    name, text = _spec_source(spec)
    overrides = _overrides(set)
    if threads is not None and (isinstance(threads, bool) or int(threads) != threads or threads < 1):
        raise ValueError(f"threads: expected a whole number >= 1, got {threads!r}")
    history = "contactsweep.run(" + (repr(name) if text is None else name) + (
        "".join(f" --set {o}" for o in overrides)) + ")"
    bar = _progress.Progress("contactsweep") if progress is True else None
    tick = bar or progress or None  # the bar, the caller's callable, or nothing
    try:
        if output is not None:
            path = os.fspath(output)
            _run_core(name, text, overrides, path, int(threads or 0), tick, history)
            return _load(path)
        roots = _scratch_roots()
        for root in roots:
            # A directory only this user can enter (mkdtemp: 0700), removed whatever happens.
            directory = tempfile.mkdtemp(prefix="contactsweep-", dir=root)
            try:
                path = os.path.join(directory, "run.h5")
                _run_core(name, text, overrides, path, int(threads or 0), tick, history)
                return _load(path)
            except ValueError as error:
                # Refused for this directory alone (no room in /dev/shm): before any work.
                if root is roots[-1] or directory not in str(error):
                    raise
            finally:
                shutil.rmtree(directory, ignore_errors=True)
    finally:
        if bar is not None:
            bar.close()
