#!/usr/bin/python3
"""Measures as formulas (issue 24, items 1 and 2): observe, observe_window and stop.

    test_observables.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

  * an observable of built-in quantities, written as the same operations, equals numpy on the
    written final and trajectory values bit for bit (built-in scene and K alike); lambda is
    exp(final_log_lambda);
  * the same with dop853, whose samples come from its steps' dense output;
  * mean_, min_, max_ over observe_window equal numpy on the trajectory samples in the window
    (the mean as a sequential sum: np.cumsum), and without a trajectory equal those of a run
    sampling every step;
  * stop on the damped oscillator's first zero of q: within one step h after the closed form;
  * a stopped lane's final_* is its state at the stop (the same bits as the trajectory of a run
    without stop at that step), its trajectory NaN after it, stop_time NaN where it never held;
  * the stop and a window without trajectory, lane by lane against numpy on every step of the
    built-in kernel's trajectory (240 lanes, per-lane parameters): stops inside a chunk, on a
    chunk's last step and in the finisher, windows from a lane's load and from a chunk's end,
    NaN marks, z carried alone, and z2_damping's z fed back but not carried;
  * exit basins (damped Henon-Heiles): every stopped lane labelled by its channel, the exits
    numbered before the attractors (attractor_period -1);
  * the same bits on 1x1, 1x2 and 2x1 ranks x threads with observe, window, stop and basin on.
"""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs, launch  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work)  # makes work/, the kernel cache in it
check = runs.check


def run(spec_text, name, ranks=0, threads=1):
    out, result = launch(binary, mpiexec, work, spec_text, name, ranks=ranks, threads=threads)
    if result.returncode != 0:
        check(f"{name} runs", False, result.stderr.strip()[-2000:])
        return None, out
    return h5py.File(out, "r"), out


def bits(x):
    x = np.ascontiguousarray(x, dtype=np.float64)
    return x.view(np.uint64)


def same(a, b):
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return a.shape == b.shape and np.array_equal(bits(a), bits(b))


# ---- observables of built-in quantities: the same bits as numpy --------------------------------
OSC = """
[scene]
{scene}
[initial]
z = 1.0
[integrator]
method = "{method}"
h = 0.01
t_end = 20.0
[grid]
q_0 = {{ from = -2.0, to = 2.0, n = 9 }}
p_0 = {{ from = -1.0, to = 1.0, n = 5 }}
[measures]
final_state = true
trajectory = {{ every = {every} }}
observe = {{ E = "p^2/2 + omega^2*(q^2/2)", L = "q*p - gamma*z", lam = "lambda", T = "t*q" }}
observe_window = {{ from = 5.0, to = 15.0 }}
"""
BUILTIN = 'name = "damped_oscillator"\nomega = 1.3\ngamma = 0.2'
AS_K = 'K = "p^2/2 + omega^2*(q^2/2) - gamma*z"\nomega = 1.3\ngamma = 0.2'


def check_osc(f, tag):
    """The observables against numpy on the written final and trajectory values."""
    omega, gamma = 1.3, 0.2
    q, p, z = f["final_q"][...], f["final_p"][...], f["final_z"][...]
    check(f"final_E = p^2/2 + omega^2*(q^2/2) bit for bit {tag}",
          same(f["final_E"][...], p**2 / 2 + omega**2 * (q**2 / 2)))
    check(f"final_L = q*p - gamma*z bit for bit {tag}",
          same(f["final_L"][...], q * p - gamma * z))
    lam = np.exp(f["final_log_lambda"][...])
    check(f"final_lam = exp(final_log_lambda) within one ulp {tag}",
          np.all(np.abs(f["final_lam"][...] - lam) <= np.spacing(lam)))
    check(f"final_T = t_end*q {tag}", same(f["final_T"][...], 20.0 * q))
    tq, tp, tz = f["traj_q"][...], f["traj_p"][...], f["traj_z"][...]
    t = f["t"][...]
    check(f"traj_E bit for bit {tag}", same(f["traj_E"][...], tp**2 / 2 + omega**2 * (tq**2 / 2)))
    check(f"traj_L bit for bit {tag}", same(f["traj_L"][...], tq * tp - gamma * tz))
    check(f"traj_T = t*q bit for bit {tag}", same(f["traj_T"][...], t * tq))
    inside = (t >= 5.0) & (t <= 15.0)
    E = f["traj_E"][...][..., inside]
    check(f"min_E, max_E over the window = numpy on the samples {tag}",
          same(f["min_E"][...], E.min(axis=-1)) and same(f["max_E"][...], E.max(axis=-1)))
    mean = np.cumsum(E, axis=-1)[..., -1] / E.shape[-1]
    check(f"mean_E = sequential sum / count, bit for bit {tag}", same(f["mean_E"][...], mean),
          f"{np.max(np.abs(f['mean_E'][...] - mean))}")
    check(f"mean_E ~ numpy's mean {tag}",
          np.allclose(f["mean_E"][...], E.mean(axis=-1), rtol=1e-13, atol=0))


for scene_name, scene in (("builtin", BUILTIN), ("K", AS_K)):
    for method in ("hybrid_leapfrog", "rk4"):
        f, _ = run(OSC.format(scene=scene, method=method, every=10), f"osc_{scene_name}_{method}")
        if f is None:
            continue
        tag = f"({scene_name}, {method})"
        check_osc(f, tag)

# dop853: its samples, interpolated inside each lane's steps (dense output), are what the
# observables read: the same checks.
dop853_spec = OSC.format(scene=BUILTIN, method="dop853", every=10).replace(
    "h = 0.01\n", "h = 0.01\nrtol = 1e-9\n")
f, _ = run(dop853_spec, "osc_builtin_dop853")
if f is not None:
    check_osc(f, "(builtin, dop853)")

# Without a trajectory every step is a sample: the statistics of a run sampling every step.
every1, _ = run(OSC.format(scene=BUILTIN, method="hybrid_leapfrog", every=1), "osc_every1")
no_traj_spec = OSC.format(scene=BUILTIN, method="hybrid_leapfrog", every=1).replace(
    "trajectory = { every = 1 }\n", "")
no_traj, _ = run(no_traj_spec, "osc_no_trajectory")
if every1 is not None and no_traj is not None:
    check("no trajectory: every step's state is a sample (= a run with trajectory every 1)",
          all(same(no_traj[f"{s}_{n}"][...], every1[f"{s}_{n}"][...])
              for s in ("mean", "min", "max") for n in ("E", "L", "T")))
    check("observables change nothing else", all(same(no_traj[v][...], every1[v][...])
                                                for v in ("final_q", "final_p", "final_z")))

# ---- stop: the damped oscillator's first zero of q ---------------------------------------------
STOP = """
[scene]
name = "damped_oscillator"
omega = 1.0
gamma = {gamma}
[integrator]
method = "{method}"
h = {h}
t_end = 10.0
[grid]
gamma = {{ values = [0.1, 0.5, 1.0] }}
[measures]
final_state = true
{extra}
stop = {{ when = "q < 0" }}
"""
for method in ("hybrid_leapfrog", "contact_splitting4", "rk4"):
    h = 0.01
    f, _ = run(STOP.format(gamma=0.1, method=method, h=h, extra=""), f"stop_{method}")
    if f is None:
        continue
    gammas = np.array([0.1, 0.5, 1.0])
    wd = np.sqrt(1.0 - gammas**2 / 4)
    t_zero = (math.pi - np.arctan(2 * wd / gammas)) / wd
    stop_time = f["stop_time"][...]
    late = stop_time - t_zero
    check(f"stop_time within one step after the first zero of q ({method})",
          np.all(late > -1e-6) and np.all(late < h + 1e-6), f"{late}")
    check(f"final_q at the stop is the first negative q ({method})",
          np.all(f["final_q"][...] < 0) and np.all(f["final_q"][...] > -2 * h))

# A stopped lane's final_* is its state at the stop: the trajectory of a run without stop.
traj, _ = run(STOP.format(gamma=0.1, method="hybrid_leapfrog", h=0.01,
                          extra="trajectory = { every = 1 }").replace(
    'stop = { when = "q < 0" }\n', ""), "stop_reference")
stopped, _ = run(STOP.format(gamma=0.1, method="hybrid_leapfrog", h=0.01,
                             extra="trajectory = { every = 1 }"), "stop_with_trajectory")
if traj is not None and stopped is not None:
    n = np.rint((stopped["stop_time"][...] - 0.0) / 0.01).astype(int)
    ok = True
    for var in ("q", "p", "z", "log_lambda"):
        ref = np.array([traj[f"traj_{var}"][k, n[k]] for k in range(3)])
        ok = ok and same(stopped[f"final_{var}"][...], ref)
    check("final_* of a stopped lane = the state at the stop (bit for bit)", ok)
    q_stopped, q_ref = stopped["traj_q"][...], traj["traj_q"][...]
    ok = all(same(q_stopped[k, : n[k] + 1], q_ref[k, : n[k] + 1]) and
             np.all(np.isnan(q_stopped[k, n[k] + 1:])) for k in range(3))
    check("its trajectory is the same until the stop and NaN after it", ok)
    check("q first negative at the stop step", all(q_ref[k, n[k]] < 0 <= q_ref[k, n[k] - 1]
                                                    for k in range(3)))

# The window's statistics of a lane that stops inside the window: over its samples up to the
# stop (every step without a trajectory: the flagged chunk is stepped again from its snapshot).
windowed, _ = run(STOP.format(gamma=0.1, method="hybrid_leapfrog", h=0.01,
                              extra='observe = { E = "p^2/2 + omega^2*(q^2/2)" }\n'
                                    'observe_window = { from = 0.5, to = 10.0 }'), "stop_window")
if traj is not None and windowed is not None:
    n = np.rint(windowed["stop_time"][...] / 0.01).astype(int)
    ok = True
    for k in range(3):
        q, p = traj["traj_q"][k, 50: n[k] + 1], traj["traj_p"][k, 50: n[k] + 1]
        E = p**2 / 2 + 1.0**2 * (q**2 / 2)
        ok = ok and same(windowed["mean_E"][k], np.cumsum(E)[-1] / len(E))
        ok = ok and same(windowed["min_E"][k], E.min()) and same(windowed["max_E"][k], E.max())
        ok = ok and same(windowed["final_E"][k], E[-1])
    check("window statistics of a stopped lane = numpy on its steps up to the stop", ok)

# ---- the every-step work against numpy, lane by lane -------------------------------------------
# The stop's flags and a window without trajectory are computed after every step inside a step
# kernel's loop, and a flagged lane is stepped again from its chunk's snapshot. Against numpy on
# every step of the built-in kernel's trajectory (a kernel compiled ahead of time, without
# formulas): stop_time the first step where the condition holds, final_* the state there,
# mean_/min_/max_ over the window's steps up to the stop (NaN where an observable was NaN on
# one of them), all bit for bit. 240 lanes over 6 omegas (per-lane parameters; more than one
# tile) from t_start = 0.5 (the clock every step's work reads) to t_end = 10.55: 1005 steps, 31
# chunks of 32 and 13 in the finisher. The stop "q < -1.2 or omega*(t - 0.5) > 6.395" holds
# first at step 640 (a chunk's last) where omega = 1, at
# step 1000 (in the finisher) where omega = 0.64 and q never went below -1.2, and never for
# the small q_0 of the low omegas; window A starts at step 0 (a lane's first sample, taken at
# its load) and ends at step 640, window B starts at step 32 (a chunk's last) and runs to t_end,
# window C starts at step 400, after the stops of omega = 1.7 (their statistics NaN).
# With z2_damping z feeds back while the run carries none of it (final q, p): the rerun from
# the snapshot needs z all the same. Each of these went unseen by the checks above: the
# finisher's flags and samples written to the main tile's slots; the stop's flag at the time of
# the step before; the snapshot's z saved where the kernel carries mu (z alone carried) or not
# where z feeds back but is not in the plan's carry; min restored from the snapshot's max;
# lane 63's flag left out of the screen; the window's first sample at a lane's load dropped; a
# chunk ending on the window's first step skipped; the NaN mark not moved to the finisher; the
# every-step window's parameters lane 0's for every lane; the step loop's clock started at 0.
EVERY_STEP = """
[scene]
name = "{scene}"
omega = 1.0
gamma = 0.15
[initial]
z = 0.5
[integrator]
method = "hybrid_leapfrog"
h = 0.01
t_start = 0.5
t_end = 10.55
[grid]
omega = {{ values = [0.3, 0.31, 0.32, 0.64, 1.0, 1.7] }}
q_0 = {{ from = 0.2, to = 2.5, n = 40 }}
[measures]
{extra}"""
EVERY_STEP_FORMULAS = {
    "damped_oscillator": 'observe = { E = "p^2/2 + omega^2*(q^2/2)", Z = "q - gamma*z", N = "sqrt(q + 1)" }\n'
                         'final_state = { vars = ["q", "p", "z"] }\n',
    "z2_damping": 'observe = { E = "p^2/2 + omega^2*(q^2/2)", N = "sqrt(q + 1)" }\n'
                  'final_state = { vars = ["q", "p"] }\n'}
for scene, formulas in EVERY_STEP_FORMULAS.items():
    ref, _ = run(EVERY_STEP.format(scene=scene, extra='final_state = { vars = ["q", "p", "z"] }\n'
                                                      'trajectory = { every = 1 }\n'), f"every_step_ref_{scene}")
    if ref is None:
        continue
    t_start, h, steps, gamma, n_lanes = 0.5, 0.01, 1005, 0.15, 240
    q, p, z = (ref[f"traj_{v}"][...].reshape(n_lanes, steps + 1) for v in "qpz")
    omega = np.repeat([0.3, 0.31, 0.32, 0.64, 1.0, 1.7], 40)[:, None]
    t = t_start + np.arange(steps + 1) * h  # the runner's clock
    with np.errstate(invalid="ignore"):
        values = {"E": p**2 / 2 + omega**2 * (q**2 / 2), "Z": q - gamma * z, "N": np.sqrt(q + 1)}
    if scene == "z2_damping":
        del values["Z"]
    held = (q < -1.2) | (omega * (t - 0.5) > 6.395)
    stop = np.where(held.any(axis=1), held.argmax(axis=1), -1)
    end = np.where(stop >= 0, stop, steps)
    lanes = np.arange(n_lanes)
    nan_in_a = [any(np.isnan(v[k, : min(end[k], 640) + 1]).any() for v in values.values()) for k in lanes]
    check(f"{scene}: the lanes stop in a chunk (before window C), on a chunk's last step, in the finisher, never; "
          f"some have NaN in the window",
          np.sum((stop > 0) & (stop < 400)) > 0 and np.sum(stop == 640) > 0 and
          np.sum(stop > 992) > 0 and np.sum(stop < 0) > 0 and 0 < sum(nan_in_a) < n_lanes,
          f"{np.unique(stop, return_counts=True)}")
    for tag, (start, stop_at) in {"A": (0.5, 6.9), "B": (0.82, 10.55), "C": (4.5, 10.55)}.items():
        # the window's steps as the program rounds them (observe_plan.cpp): A 0 to 640, B 32 to
        # 1005, C 400 to 1005 (omega = 1.7 stops before it: no sample, NaN)
        first = math.ceil((start - t_start) / h - 1e-9)
        last = min(math.floor((stop_at - t_start) / h + 1e-9), steps)
        window = f"from = {start}, to = {stop_at}"
        f, _ = run(EVERY_STEP.format(scene=scene, extra=formulas +
                                     f'stop = {{ when = "q < -1.2 or omega*(t - 0.5) > 6.395" }}\n'
                                     f"observe_window = {{ {window} }}\n"), f"every_step_{scene}_{tag}")
        if f is None:
            continue
        got = lambda name: f[name][...].reshape(n_lanes)  # noqa: E731
        check(f"{scene} {tag}: stop_time = the first step where the condition holds, bit for bit",
              same(got("stop_time"), np.where(stop >= 0, t[stop], np.nan)),
              f"lanes {np.nonzero(bits(got('stop_time')) != bits(np.where(stop >= 0, t[stop], np.nan)))[0][:8]}")
        finals = {"q": q, "p": p} | ({"z": z} if "Z" in values else {}) | values
        wrong = [n for n, v in finals.items() if not same(got(f"final_{n}"), v[lanes, end])]
        check(f"{scene} {tag}: final_* at the stop (at t_end where none), bit for bit", not wrong, f"{wrong}")
        wrong = []
        for name, v in values.items():
            expected = {s: np.full(n_lanes, np.nan) for s in ("mean", "min", "max")}
            for k in lanes:
                top = min(last, end[k])
                if top < first or any(np.isnan(w[k, first: top + 1]).any() for w in values.values()):
                    continue
                x = v[k, first: top + 1]
                expected["mean"][k], expected["min"][k], expected["max"][k] = np.cumsum(x)[-1] / len(x), x.min(), x.max()
            wrong += [f"{s}_{name}" for s in expected if not same(got(f"{s}_{name}"), expected[s])]
        check(f"{scene} {tag}: mean_, min_, max_ over the window's steps up to the stop = numpy, "
              f"bit for bit", not wrong, f"{wrong}")

# The exit channel as a formula (rounded to the nearest whole number), and exits in a basin map.
labelled, _ = run(STOP.format(gamma=0.1, method="rk4", h=0.01, extra="basin = { exact_trap = false }").replace(
    'stop = { when = "q < 0" }', 'stop = { when = "q < 0", label = "1 + 10*gamma + 0.2" }'),
    "stop_label")
if labelled is not None:
    check("label formula: stop_exit = round(1 + 10*gamma + 0.2)",
          list(labelled["stop_exit"][...]) == [2, 6, 11], f"{labelled['stop_exit'][...]}")
    check("each channel an exit of the basin map, numbered in the order of the channels",
          list(labelled["attractor_period"][...]) == [-1, -1, -1] and
          list(labelled["attractor_q"][...]) == [2.0, 6.0, 11.0] and
          list(labelled["basin"][...]) == [1, 2, 3] and
          np.allclose(labelled["settle_time"][...], labelled["stop_time"][...]))

never, _ = run(STOP.format(gamma=0.1, method="rk4", h=0.01, extra="").replace(
    '"q < 0"', '"q > 5 or (p > 5 and q < -5)"'), "stop_never")
if never is not None:
    check("stop_time is NaN where the condition never held", np.all(np.isnan(never["stop_time"][...])))
    check("status ok there", np.all(never["status"][...] == 0))

# ---- exit basins: damped Henon-Heiles from rest -------------------------------------------------
HH = """
[scene]
K = "p1^2/2 + p2^2/2 + q1^2/2 + q2^2/2 + q1^2*q2 - q2^3/3 - gamma*z"
gamma = 0.05
[integrator]
method = "hybrid_leapfrog"
h = 0.01
t_end = 60.0
[grid]
q1_0 = { from = -0.9, to = 0.9, n = 32 }
q2_0 = { from = -0.9, to = 0.9, n = 24 }
[measures]
final_state = { vars = ["q1", "q2"] }
basin = {}
observe = { E = "p1^2/2 + p2^2/2 + q1^2/2 + q2^2/2 + q1^2*q2 - q2^3/3" }
observe_window = { from = 0.0, to = 10.0 }
stop = { when = "q1^2 + q2^2 > 4", exits = ["q2 > 0.5773502691896257*q1 and q2 > -0.5773502691896257*q1", "q1 < 0", "q1 >= 0"] }
"""
hh, hh_path = run(HH, "henon_heiles")
if hh is not None:
    exit_ = hh["stop_exit"][...]
    basin = hh["basin"][...]
    stopped = ~np.isnan(hh["stop_time"][...])
    check("every stopped lane has a channel, the others none",
          np.all((exit_ > 0) == stopped) and set(np.unique(exit_)) <= {0, 1, 2, 3})
    periods = hh["attractor_period"][...]
    n_exits = int(np.sum(periods == -1))
    check("exits numbered first in the attractor table", n_exits >= 2 and
          np.all(periods[:n_exits] == -1) and np.all(periods[n_exits:] >= 0), f"{periods}")
    channel_of_label = {int(l): int(c) for l, c, per in zip(hh["attractor_label"][...],
                                                         hh["attractor_q1"][...], periods) if per == -1}
    ok = all(channel_of_label.get(int(basin[i]), -1) == exit_[i] for i in zip(*np.nonzero(stopped)))
    check("a stopped lane's basin label is its exit's", ok)
    q1, q2 = hh["final_q1"][...], hh["final_q2"][...]
    r2 = q1**2 + q2**2
    check("final state at the stop is past the escape radius", np.all(r2[stopped] > 4))
    check("trapped lanes end inside", np.all(r2[~stopped] <= 4))
    for ranks, threads in ((0, 2), (2, 1)):
        other, path = run(HH, f"henon_heiles_{ranks}x{threads}", ranks=ranks, threads=threads)
        if other is not None:
            r = subprocess.run([sys.executable, compare, hh_path, path], capture_output=True, text=True)
            check(f"same bits on {max(ranks, 1)} rank(s) x {threads} thread(s)", r.returncode == 0,
                  r.stdout + r.stderr)

# ---- a basin map's trajectory after the lane settled with early stop ---------------------------
# A lane whose basin is decided stops costing time; its trajectory ends there. The samples it
# never reached were left at the columns' zeros (q = p = E = 0, values an orbit can hold, and
# the energy trap settles a lane below the barrier at t = 0: zeros after its first sample).
# Now they are NaN, as after a stop or a failure. The reference is the same map integrated to
# t_end (early_stop = false), which must hold the same bits wherever the early-stopped run has a
# sample; on-line anchors (exact_trap = false) settle the lanes mid-run, the trap at t = 0.
SETTLE = """
[scene]
{scene}
[integrator]
method = "rk4"
h = 0.02
t_end = 60.0
[grid]
q_0 = {{ from = -1.8, to = 1.8, n = 10 }}
p_0 = {{ from = -1.0, to = 1.0, n = 6 }}
[measures]
basin = {{ exact_trap = {trap}, early_stop = {early} }}
final_state = {{ vars = ["q", "p"] }}
trajectory = {{ every = 25 }}
{formulas}
"""
DW = 'name = "double_well"\ngamma = 1.0'
DW_K = 'K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"\na = 1.0\ngamma = 1.0'
E_FORMULAS = ('observe = { E = "p^2/2 + (q^2 - a*a)^2/2" }\n'
              'observe_window = { from = 0.0, to = 60.0 }')
for scene_name, scene, formulas in (("builtin", DW, ""), ("builtin_formulas", DW, E_FORMULAS),
                                    ("K_formulas", DW_K, E_FORMULAS.replace("a*a", "1.0"))):
    for trap in ("false", "true"):
        tag = f"({scene_name}, exact_trap = {trap})"
        name = f"settle_{scene_name}_{trap}"
        early, _ = run(SETTLE.format(scene=scene, trap=trap, early="true", formulas=formulas), name)
        full, _ = run(SETTLE.format(scene=scene, trap=trap, early="false", formulas=formulas),
                      name + "_full")
        if early is None or full is None:
            continue
        t = early["t"][...]
        settle = early["settle_time"][...]
        check(f"every lane settled {tag}", np.all(np.isfinite(settle)), f"{settle}")
        tq, fq = early["traj_q"][...], full["traj_q"][...]
        kept = ~np.isnan(tq)
        check(f"the full run's trajectory is finite {tag}", np.all(np.isfinite(fq)))
        for v in ("traj_q", "traj_p") + (("traj_E",) if formulas else ()):
            a, b = early[v][...], full[v][...]
            check(f"{v}: the full run's bits where the lane ran, NaN after {tag}",
                  same(a[kept], b[kept]) and np.all(np.isnan(a[~kept])),
                  f"{np.sum((a == 0.0) & (b != 0.0))} zeros where the lane had not run")
        # NaN after the lane's end only, never before its settle time: samples at t <= settle
        # are all there, and every lane has its first sample (t_start).
        before = t[None, None, :] <= settle[..., None]
        check(f"no sample missing up to the settle time {tag}", np.all(kept[before]) and
              np.all(kept[..., 0]))
        if trap == "true":
            # below the barrier at the start: decided there, the first sample its only one
            at_start = settle == 0.0
            check(f"a lane the trap settles at t_start has one sample, the others more {tag}",
                  np.any(at_start) and np.all(kept.sum(axis=-1)[at_start] == 1) and
                  np.all(kept.sum(axis=-1)[~at_start] > 1))
        else:
            check(f"anchors settle the lanes mid-run {tag}",
                  np.all(settle > 0.0) and np.all(kept.sum(axis=-1) > 1) and np.any(~kept))
        if formulas:
            # the window's statistics are over the samples the lane had, as for a stop inside it
            E = np.where(kept, early["traj_E"][...], np.nan)
            mean = np.array([np.cumsum(e[~np.isnan(e)])[-1] / np.sum(~np.isnan(e))
                             for e in E.reshape(-1, E.shape[-1])]).reshape(E.shape[:-1])
            check(f"mean_E over the samples up to the lane's end {tag}",
                  same(early["mean_E"][...], mean))
            check(f"min_E, max_E over them {tag}", same(early["min_E"][...], np.nanmin(E, axis=-1))
                  and same(early["max_E"][...], np.nanmax(E, axis=-1)))

print(f"{runs.failures} failed")
sys.exit(1 if runs.failures else 0)
