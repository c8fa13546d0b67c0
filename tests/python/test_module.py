"""The Python module's contract (docs/python.md) beyond the sweeps: specs given as text and as
dicts (with a K), the temporary file gone, bad input as the CLI's message, Ctrl-C, the lists."""
import math
import os
import pathlib
import re
import signal
import subprocess
import sys
import threading
import tomllib

import pytest

import contactsweep
from contactsweep import _toml
from conftest import CLI, ROOT, assert_dataset_is_file, cli_run

SMALL_MAP = """\
[scene]
name = "double_well"
[integrator]
h = 0.01
t_end = 1.0
[grid]
q_0 = { from = -3.0, to = 3.0, n = 64 }
p_0 = { from = -3.0, to = 3.0, n = 64 }
[measures]
basin = {}
final_state = true
"""


def test_text_spec_without_output_equals_the_cli_and_leaves_nothing(tmp_path, private_tmpdir):
    (tmp_path / "map.toml").write_text(SMALL_MAP)
    assert cli_run(tmp_path / "map.toml", tmp_path / "cli.h5").returncode == 0
    ds = contactsweep.run(SMALL_MAP, threads=1, progress=False)
    assert_dataset_is_file(ds, tmp_path / "cli.h5")
    assert ds.basin.shape == (64, 64)
    assert list(private_tmpdir.iterdir()) == []  # the private directory and its file are gone


def test_runs_from_several_threads_take_turns(tmp_path):
    """run() from four threads at once: each file is the CLI's. In a child process, so that a
    crash (HDF5 is not thread-safe; without the module's lock the interpreter died) fails this
    test alone."""
    (tmp_path / "map.toml").write_text(SMALL_MAP)
    assert cli_run(tmp_path / "map.toml", tmp_path / "cli.h5").returncode == 0
    code = f"""
import threading, contactsweep
def one(k):
    contactsweep.run({str(tmp_path / "map.toml")!r}, threads=1, progress=False,
                     output={str(tmp_path)!r} + f"/thread{{k}}.h5")
threads = [threading.Thread(target=one, args=(k,)) for k in range(4)]
for t in threads: t.start()
for t in threads: t.join()
"""
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           stdin=subprocess.DEVNULL, timeout=120)
    assert child.returncode == 0, child.stderr[-2000:]
    for k in range(4):
        assert_dataset_is_file(contactsweep._load(tmp_path / f"thread{k}.h5"), tmp_path / "cli.h5")


def test_without_tmpdir_the_scratch_is_dev_shm_and_is_removed(tmp_path, monkeypatch):
    for name in ("TMPDIR", "TEMP", "TMP"):
        monkeypatch.delenv(name, raising=False)
    assert contactsweep._scratch_roots()[0] == "/dev/shm"
    (tmp_path / "map.toml").write_text(SMALL_MAP)
    assert cli_run(tmp_path / "map.toml", tmp_path / "cli.h5").returncode == 0
    ours = lambda: {p for p in os.listdir("/dev/shm") if p.startswith("contactsweep-")}  # noqa: E731
    before = ours()
    ds = contactsweep.run(SMALL_MAP, progress=False)
    assert_dataset_is_file(ds, tmp_path / "cli.h5")
    assert ours() <= before


def test_dict_spec_with_k_equals_the_cli(tmp_path):
    # The forced, damped Duffing oscillator as K; the dict's axis order is the grid's order.
    spec = {
        "title": "Duffing \"forced\" — a dict",
        "scene": {"K": "p^2/2 - q^2/2 + q^4/4 - F*q*cos(omega*t) + gamma*z",
                  "F": 0.3, "omega": 1.2, "gamma": 0.15},
        "integrator": {"method": "rk4", "h": 0.01, "t_end": 2.0},
        "grid": {"p_0": {"from": -1.0, "to": 1.0, "n": 5}, "q_0": {"values": [-1.0, 0.5, 1.0]}},
        "measures": {"final_state": True},
    }
    text = """\
title = "Duffing \\"forced\\" — a dict"
[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(omega*t) + gamma*z"
F = 0.3
omega = 1.2
gamma = 0.15
[integrator]
method = "rk4"
h = 0.01
t_end = 2.0
[grid]
p_0 = { from = -1.0, to = 1.0, n = 5 }
q_0 = { values = [-1.0, 0.5, 1.0] }
[measures]
final_state = true
"""
    (tmp_path / "duffing.toml").write_text(text)
    cli = cli_run(tmp_path / "duffing.toml", tmp_path / "cli.h5")
    assert cli.returncode == 0, cli.stderr
    ds = contactsweep.run(spec, progress=False)
    assert_dataset_is_file(ds, tmp_path / "cli.h5")
    assert ds.final_q.dims == ("p_0", "q_0") and ds.final_q.shape == (5, 3)
    assert ds.attrs["K"] == spec["scene"]["K"]


WELLS_MAP = """\
[scene]
K = "{K}"
a = 1.0
gamma = 0.5
[integrator]
method = "rk4"
h = 0.02
t_end = 20.0
[grid]
q_0 = {{ from = -3.0, to = 3.0, n = 24 }}
p_0 = {{ from = -1.0, to = 1.0, n = 8 }}
[measures]
basin = {{}}
final_state = true
"""


@pytest.mark.slow
def test_two_ks_in_one_process_keep_their_own_wells(tmp_path):
    """The energy trap keeps each parameter set's wells for the process's life (EnergyTrap::
    wells_for), keyed by the K too (a step kernel's table): two K's with the same parameters and
    grid, one after the other in one process, each get their own wells. The second's map is the
    CLI's file bit for bit, and its attractors sit at its own minima q = ±2a, not the first's ±a."""
    first = WELLS_MAP.format(K="p^2/2 + (q^2 - a^2)^2/2 - gamma*z")
    second = WELLS_MAP.format(K="p^2/2 + (q^2 - 4*a^2)^2/2 - gamma*z")
    (tmp_path / "second.toml").write_text(second)
    cli = cli_run(tmp_path / "second.toml", tmp_path / "cli.h5")
    assert cli.returncode == 0, cli.stderr
    ds_first = contactsweep.run(first, threads=1, progress=False)
    assert ds_first.attrs["energy_trap"] == "used"
    ds = contactsweep.run(second, threads=1, progress=False)
    assert ds.attrs["energy_trap"] == "used"
    assert_dataset_is_file(ds, tmp_path / "cli.h5")
    tolerance = 1e-3  # measures.basin.tolerance's default: how near its attractor a lane settles
    assert sorted(ds.attractor_q.values.tolist()) == pytest.approx([-2.0, 2.0], abs=tolerance)
    assert sorted(ds_first.attractor_q.values.tolist()) == pytest.approx([-1.0, 1.0], abs=tolerance)


FORMULAS_RUN = """[scene]
K = "p^2/2 + q^2/2 - gamma*z"
gamma = 0.1
[integrator]
h = 0.01
t_end = 2.0
[grid]
q_0 = {{ values = [0.5, 1.0] }}
[measures]
final_state = {{}}
{formulas}
"""


def test_one_k_with_other_formulas_in_one_process_gets_its_own(tmp_path):
    """Each run's formulas are its own when several runs of one K load their kernels into one
    process: the kernels' tables were GNU unique symbols named by K and the formulas' fixed
    struct name, which the loader merges across libraries, so a second run of the same K took
    the first one's formulas (final_E of the first E, every stop at t = 0). Each run here is the
    CLI's file bit for bit."""
    runs = ['observe = { E = "p^2/2 + q^2/2" }\nstop = { when = "t < 1" }',
            'observe = { E = "q" }\nstop = { when = "t > 1.5" }',
            'observe = { E = "q" }\nstop = { when = "t > 1.5", label = "q + 2" }']
    for k, formulas in enumerate(runs):
        spec = FORMULAS_RUN.format(formulas=formulas)
        (tmp_path / f"{k}.toml").write_text(spec)
        cli = cli_run(tmp_path / f"{k}.toml", tmp_path / f"{k}.h5")
        assert cli.returncode == 0, cli.stderr
        assert_dataset_is_file(contactsweep.run(spec, threads=1, progress=False),
                               tmp_path / f"{k}.h5")
    ds = contactsweep.run(FORMULAS_RUN.format(formulas=runs[1]), threads=1, progress=False)
    assert ds.stop_time.values.tolist() == pytest.approx([1.51, 1.51], abs=1e-12)
    assert ds.final_E.values.tolist() == ds.final_q.values.tolist()


def test_toml_of_a_dict_reads_back_the_same():
    spec = {"title": "a \"b\"\n\\ c\x7f é", "n": 3, "on": False,
            "s": {"x": 0.1, "tiny": 5e-324, "big": -1.7976931348623157e308, "inf": math.inf,
                  "weird key": [1, 2.5, "x"], "t": {"a": {"b": [[]]}}}}
    back = tomllib.loads(_toml.dumps(spec))
    assert back == spec
    assert list(back["s"]) == list(spec["s"])  # key order kept (the grid's order)
    with pytest.raises(ValueError, match="no TOML form"):
        _toml.dumps({"s": {"x": object()}})


# (name, spec file edit, overrides, fragment of the CLI's message): the CLI's bad-input table
# (tests/test_cli_errors.sh) where it applies to run().
BAD_INPUT = [
    ("unknown key", ("h = 0.01", 'metod = "rk4"'), [], "did you mean 'integrator.method'"),
    ("unknown scene", ("double_well", "double_wel"), [], "coupled_oscillators"),
    ("malformed TOML", ("t_end = 1.0", "t_end = = 1.0"), [], ":5:9: malformed TOML"),
    ("t_end not whole steps", ("t_end = 1.0", "t_end = 1.005"), [], "whole number of steps"),
    ("--set of an unknown key", None, ["integrator.hh=0.1"], "integrator.hh"),
    ("--set h = 0", None, ["integrator.h=0"], "integrator.h"),
    ("unknown function in K", ('name = "double_well"', 'K = "p^2/2 + sinn(q)"'), [],
     "unknown function 'sinn' at column 9"),
    ("both K and name", ('name = "double_well"', 'name = "double_well"\nK = "p^2/2 + q^2/2"'), [],
     "[scene] has both name and K"),
]


def cli_message(stderr):
    match = re.search(r"^contactsweep: error: (.*)\Z", stderr.strip(), re.S | re.M)
    assert match, stderr
    return match.group(1)


@pytest.mark.parametrize("edit, overrides, fragment",
                         [pytest.param(*case[1:], id=case[0]) for case in BAD_INPUT])
def test_bad_input_is_value_error_with_the_cli_message(tmp_path, edit, overrides, fragment):
    text = SMALL_MAP if edit is None else SMALL_MAP.replace(*edit, 1)
    spec = tmp_path / "spec.toml"
    spec.write_text(text)
    cli = cli_run(spec, tmp_path / "cli.h5", overrides)
    assert cli.returncode == 2
    with pytest.raises(ValueError) as error:
        contactsweep.run(spec, set=dict(o.split("=", 1) for o in overrides),
                         output=tmp_path / "module.h5", progress=False)
    assert str(error.value) == cli_message(cli.stderr)
    assert fragment in str(error.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]  # nothing written


def test_unreadable_spec_and_existing_output_are_value_errors(tmp_path):
    missing = tmp_path / "missing.toml"
    cli = cli_run(missing, tmp_path / "out.h5")
    with pytest.raises(ValueError) as error:
        contactsweep.run(missing, progress=False)
    assert str(error.value) == cli_message(cli.stderr) and "missing.toml" in str(error.value)
    (tmp_path / "kept.h5").write_bytes(b"not touched")
    with pytest.raises(ValueError, match="pass --force"):
        contactsweep.run(SMALL_MAP, output=tmp_path / "kept.h5", progress=False)
    assert (tmp_path / "kept.h5").read_bytes() == b"not touched"


LONG_RUN = """\
[scene]
name = "double_well"
[integrator]
h = 0.01
t_end = 10000.0
[grid]
q_0 = { from = -3.0, to = 3.0, n = 128 }
p_0 = { from = -3.0, to = 3.0, n = 128 }
[measures]
final_state = true
"""


def interrupt_after(seconds):
    """SIGINT to this process from a timer thread, as Ctrl-C in a terminal would send it."""
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize("with_output", [True, False], ids=["output", "no_output"])
def test_ctrl_c_raises_keyboard_interrupt_and_leaves_nothing(tmp_path, private_tmpdir, with_output):
    # 16384 points x 10^6 steps: minutes on any machine, so the signal comes mid-run; then the
    # same output is free for the next run.
    output = tmp_path / "out.h5" if with_output else None
    progress = []
    timer = interrupt_after(1.0)
    try:
        with pytest.raises(KeyboardInterrupt):
            contactsweep.run(LONG_RUN, threads=2, output=output, progress=progress.append)
    finally:
        timer.cancel()
    assert progress and progress[-1] < 1.0
    # Nothing under the output's name, no journal (only this build could resume it).
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tmp"]
    assert list(private_tmpdir.iterdir()) == []


def test_scenes_and_methods_are_what_the_cli_lists():
    def names(command):
        out = subprocess.run([CLI, command], capture_output=True, text=True, check=True).stdout
        return [line.split()[0] for line in out.splitlines() if line and not line[0].isspace()]

    scenes, methods = contactsweep.scenes(), contactsweep.methods()
    assert [s["name"] for s in scenes] == names("scenes")
    assert [m["name"] for m in methods] == names("methods")
    well = next(s for s in scenes if s["name"] == "double_well")
    assert [p["name"] for p in well["parameters"]] == ["a", "gamma"]
    assert {m["name"]: m["order"] for m in methods}["rk4"] == 4
    # The step size's kind as the CLI prints it, method by method.
    out = subprocess.run([CLI, "methods"], capture_output=True, text=True, check=True).stdout
    printed = [line.split(": ", 1)[1].startswith("adaptive")
               for line in out.splitlines() if line.strip().startswith("step size:")]
    assert printed == [m["adaptive"] for m in methods]
    assert {m["name"]: m["adaptive"] for m in methods}["dop853"] is True


def test_quickstart_draws_a_basin_map(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    subprocess.run([sys.executable, ROOT / "examples" / "quickstart.py"], cwd=tmp_path, env=env,
                   check=True, stdin=subprocess.DEVNULL)
    png = tmp_path / "basins.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
