#!/usr/bin/python3
"""A kernel built at run time holds the basin mappers its run uses and no others
(engine/mappers/mapper_choice.hpp), and an adaptive method's dense output only where its run
samples inside steps (BlockRunner's DenseOutput; docs/performance.md, "only what a run uses").

    test_kernel_parts.py CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS WORKDIR

* The double well as K without a basin map: its kernel's symbol table names none of the
  mappers' code (the energy trap and its wells, the recurrences, the stroboscopic cycles; the
  anchor test is inlined whole, so it leaves no name to look for). The basin columns of a runner
  with only its plan's mappers against one with all: test_kernel_parts.cpp.
* The same K with a basin map to t_end (no early stop): a step kernel with the trap's uses of K
  (the wells' search: WellFinder), the energy trap itself and the other mappers in the
  program's runner; its final states are the same bits as the run without the map, which had
  no mapper at all, and as the same map in 2 x 1 ranks x threads.
* A forced K on its stroboscopic map without recurrences: the energy trap is asked for
  (exact_trap's default), but a K that reads t has none, so the run builds a step kernel and
  the program's runner holds the stroboscopic cycles: no kernel names a mapper.
* The built-in double well with lyapunov and no basin map (a kernel built at run time): no
  mapper either, and its final states are the built-in kernel's (every mapper, none active).
* The built-in double well with observe: a step kernel, whose final states are the built-in
  kernel's; with a stop and a window without trajectory (their work after every step in the
  step kernel's loop) its final states, statistics and stop times are the bits of a whole
  kernel's (the same run with lyapunov). Its basin map with formulas: a step kernel with the
  trap's uses of K, whose map is the built-in kernel's bits, its stops and statistics a whole
  kernel's.
* The double well as K with dop853 and final states alone: no dense output compiled in; with
  a trajectory it is, and the final states are the same bits (samples never change the steps).
"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from contactsweep_runs import Runs  # noqa: E402

binary, mpiexec, compare, work = sys.argv[1:5]
runs = Runs(binary, mpiexec, work, compare=compare)
check = runs.check

MAPPERS = ("EnergyTrap<", "WellFinder<", "Recurrences<", "StroboscopicCycles<")
DENSE = "Dop853Dense<"  # dop853's continuous extension (numerics/dop853_dense.hpp)
# A step kernel's entry (engine/step_kernel.hpp): a K's run with a fixed-step method builds
# one, and the program's runner holds the mappers (the energy trap's uses of K in the kernel).
STEP_ENTRY = "contactsweep_step_kernel"


def parts_in(cache, parts=MAPPERS):
    """The parts named in the symbol table of each kernel the cache holds."""
    found = {}
    for name in sorted(os.listdir(cache)):
        if name.startswith("kernel-") and name.endswith(".so"):
            symbols = subprocess.run(["nm", "-C", os.path.join(cache, name)], capture_output=True,
                                     text=True, check=True).stdout
            found[name] = {m for m in parts if m in symbols}
    return found


def run_in_fresh_cache(spec_text, name, ranks=0, threads=1, parts=MAPPERS):
    """The run's output and the parts in the kernels of a cache of its own (0700)."""
    cache = tempfile.mkdtemp(prefix=name + "_cache.", dir=work)
    out, _ = runs.launch(spec_text, name, ranks=ranks, threads=threads,
                         env_extra={"CONTACTSWEEP_CACHE": cache})
    return out, parts_in(cache, parts)


def final_state(path):
    with h5py.File(path, "r") as f:
        return {k: f[k][...] for k in f if k.startswith("final_")}


def same_final_state(name, a, b):
    sa, sb = final_state(a), final_state(b)
    same = sa.keys() == sb.keys() and bool(sa) and all(
        np.array_equal(sa[k], sb[k], equal_nan=True) for k in sa)
    check(name, same, f"{sorted(sa)} vs {sorted(sb)}")


WELL = """[scene]
K = "p^2/2 + (q^2 - a*a)^2/2 - gamma*z"
a = 1.0
gamma = 0.25
[initial]
z = 1.0
lambda = 1.0
[integrator]
method = "hybrid_leapfrog"
h = 0.01
t_end = 40.0
[grid]
q_0 = { from = -2.5, to = 2.5, n = 12 }
p_0 = { from = -2.0, to = 2.0, n = 10 }
[measures]
final_state = true
"""

plain, found = run_in_fresh_cache(WELL + "trajectory = { every = 100 }\n", "well_k_plain")
check("K without a basin map: one kernel, no mapper compiled in",
      len(found) == 1 and found[next(iter(found))] == set(), f"{found}")

mapped, found = run_in_fresh_cache(WELL + "basin = { early_stop = false }\n", "well_k_map",
                                   parts=MAPPERS + (STEP_ENTRY,))
check("K's basin map: a step kernel with the wells' search, the energy trap and the other "
      "mappers in the program (no orbit kernel: its attractors are fixed points)",
      list(found.values()) == [{STEP_ENTRY, "WellFinder<"}], f"{found}")
if plain and mapped:
    same_final_state("K's final states: the same bits with the basin map's mappers and without",
                     plain, mapped)
    with h5py.File(mapped, "r") as f:
        labels = set(np.unique(f["basin"][...]).tolist())
    check("K's basin map labels its two wells", labels <= {0, 1, 2} and {1, 2} <= labels,
          f"{labels}")
    spread, _ = runs.launch(WELL + "basin = { early_stop = false }\n", "well_k_map_2x1", ranks=2)
    if spread:
        runs.same_bits("K's basin map: 2 x 1 ranks x threads has the bits of 1 x 1", mapped,
                       spread, count=2)

FORCED = """[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"
delta = 0.3
F = 0.2
Omega = 1.2
[initial]
z = 0.0
lambda = 1.0
[integrator]
method = "rk4"
h = 0.02617993877991494
t_end = 104.71975511965977
[grid]
q_0 = { from = -1.5, to = 1.5, n = 6 }
p_0 = { from = -1.0, to = 1.0, n = 4 }
[measures]
basin = { period = 5.235987755982989, recurrence = false }
"""
_, found = run_in_fresh_cache(FORCED, "forced_k_strobe", parts=MAPPERS + (STEP_ENTRY,))
runner = [m for m in found.values() if m]
check("forced K on its stroboscopic map (no energy trap: K reads t; recurrences off): a step "
      "kernel, no mapper in any kernel (the stroboscopic cycles run in the program)",
      runner == [{STEP_ENTRY}], f"{found}")

BUILTIN = WELL.replace('K = "p^2/2 + (q^2 - a*a)^2/2 - gamma*z"', 'name = "double_well"')
builtin, _ = runs.launch(BUILTIN, "well_builtin")
tangent, found = run_in_fresh_cache(BUILTIN + "lyapunov = {}\n", "well_builtin_lyapunov")
check("built-in double well with lyapunov: its kernel has no mapper",
      len(found) == 1 and found[next(iter(found))] == set(), f"{found}")
if builtin and tangent:
    same_final_state("built-in double well: the same final states with lyapunov's kernel",
                     builtin, tangent)

# Measures as formulas: a step kernel holds them (for a built-in scene too), their work after
# every step (the stop's condition, a window without trajectory) in its step loop. The same run
# with lyapunov builds a whole kernel (the tangent is K's code): the same bits.
OBSERVE = ('trajectory = { every = 100 }\nobserve = { E = "p^2/2 + (q^2 - a*a)^2/2", L = "lambda*z" }\n')
EVERY_STEP = ('observe = { E = "p^2/2 + (q^2 - a*a)^2/2", L = "lambda*z" }\n'
              'observe_window = { from = 5.0, to = 30.0 }\nstop = { when = "q*p > 1.5" }\n')
observed, found = run_in_fresh_cache(BUILTIN + OBSERVE, "well_builtin_observe",
                                     parts=MAPPERS + (STEP_ENTRY,))
check("built-in double well with observe at its samples: a step kernel, no mapper",
      list(found.values()) == [{STEP_ENTRY}], f"{found}")
if builtin and observed:
    ours, theirs = final_state(observed), final_state(builtin)
    check("built-in double well: the same final states on its step kernel",
          bool(theirs) and all(np.array_equal(ours[k], v, equal_nan=True)
                               for k, v in theirs.items()), f"{sorted(theirs)}")
watched, found = run_in_fresh_cache(BUILTIN + EVERY_STEP, "well_builtin_stop",
                                    parts=MAPPERS + (STEP_ENTRY,))
check("with a stop and a window without trajectory: a step kernel, no mapper",
      list(found.values()) == [{STEP_ENTRY}], f"{found}")
whole, found = run_in_fresh_cache(BUILTIN + EVERY_STEP + "lyapunov = {}\n",
                                  "well_builtin_stop_lyapunov", parts=MAPPERS + (STEP_ENTRY,))
check("the same with lyapunov: a whole kernel, no mapper",
      list(found.values()) == [set()], f"{found}")
if watched and whole:
    with h5py.File(watched, "r") as a, h5py.File(whole, "r") as b:
        names = [n for n in a if n.startswith(("final_", "mean_", "min_", "max_", "stop_"))]
        stopped = np.isfinite(a["stop_time"][...])
        check("the stop holds for some lanes and not for others",
              0 < np.count_nonzero(stopped) < stopped.size, f"{np.count_nonzero(stopped)}")
        check("the step kernel's stop and window: the bits of the whole kernel's",
              len(names) >= 8 and all(np.array_equal(a[n][...], b[n][...], equal_nan=True)
                                      for n in names),
              f"{[n for n in names if not np.array_equal(a[n][...], b[n][...], equal_nan=True)]}")

# A built-in scene's basin map with formulas: a step kernel from its header with the trap's uses
# of K (its wells' search), the trap and the other mappers in the program's runner; the same map
# with lyapunov builds a whole kernel, whose trap reads the scene's own type: the same bits.
MAP_OBSERVE = ('basin = { early_stop = false }\nobserve = { E = "p^2/2 + (q^2 - a*a)^2/2" }\n'
               'observe_window = { from = 5.0, to = 30.0 }\nstop = { when = "t > 2 and p > 0.8" }\n')
map_observed, found = run_in_fresh_cache(BUILTIN + MAP_OBSERVE, "well_builtin_map_observe",
                                         parts=MAPPERS + (STEP_ENTRY,))
check("built-in double well's basin map with formulas: a step kernel with the wells' search, "
      "no other mapper in it", list(found.values()) == [{STEP_ENTRY, "WellFinder<"}], f"{found}")
map_whole, found = run_in_fresh_cache(BUILTIN + MAP_OBSERVE + "lyapunov = {}\n",
                                      "well_builtin_map_lyapunov", parts=MAPPERS + (STEP_ENTRY,))
check("the same map with lyapunov: a whole kernel with the trap and its wells",
      [sorted(v) for v in found.values()] == [["EnergyTrap<", "WellFinder<"]], f"{found}")
if map_observed and map_whole:
    with h5py.File(map_observed, "r") as a, h5py.File(map_whole, "r") as b:
        names = [n for n in a if n.startswith(("final_", "mean_", "min_", "max_", "stop_"))
                 or n in ("basin", "settle_time")]
        labels = set(np.unique(a["basin"][...]).tolist())
        stopped = np.isfinite(a["stop_time"][...])
        check("the map labels both wells and the stop holds for some lanes only",
              {1, 2} <= labels and 0 < np.count_nonzero(stopped) < stopped.size,
              f"{labels}, {np.count_nonzero(stopped)} stopped")
        check("the built-in's map on a step kernel: the bits of the whole kernel's",
              len(names) >= 8 and all(np.array_equal(a[n][...], b[n][...], equal_nan=True)
                                      for n in names),
              f"{[n for n in names if not np.array_equal(a[n][...], b[n][...], equal_nan=True)]}")

# The same map with observe alone against the built-in kernel's (compiled ahead of time, no
# formulas): the step kernel's trap decides as the built-in's, bit for bit (a step kernel whose
# trap went unused settled every lane later: settle_time differed while every check above held).
BUILTIN_MAP = BUILTIN.replace("final_state = true", "final_state = true\nbasin = {}")
builtin_map, _ = runs.launch(BUILTIN_MAP, "well_builtin_map")
observed_map, found = run_in_fresh_cache(BUILTIN_MAP + 'observe = { E = "p^2/2 + (q^2 - a*a)^2/2" }\n',
                                         "well_builtin_map_observe_only", parts=MAPPERS + (STEP_ENTRY,))
check("built-in double well's basin map with observe alone: a step kernel with the wells' search",
      list(found.values()) == [{STEP_ENTRY, "WellFinder<"}], f"{found}")
if builtin_map and observed_map:
    with h5py.File(builtin_map, "r") as a, h5py.File(observed_map, "r") as b:
        names = [n for n in a if n in ("basin", "settle_time", "status") or n.startswith("final_")]
        check("its basin, settle_time and final states: the built-in kernel's bits",
              len(names) >= 6 and all(np.array_equal(a[n][...], b[n][...], equal_nan=True) for n in names),
              f"{[n for n in names if not np.array_equal(a[n][...], b[n][...], equal_nan=True)]}")

DOP853 = WELL.replace('method = "hybrid_leapfrog"', 'method = "dop853"\nrtol = 1e-9')
final_only, found = run_in_fresh_cache(DOP853, "well_k_dop853", parts=MAPPERS + (DENSE,))
check("K with dop853, final states alone: no dense output and no mapper compiled in",
      len(found) == 1 and found[next(iter(found))] == set(), f"{found}")
sampled, found = run_in_fresh_cache(DOP853 + "trajectory = { every = 100 }\n", "well_k_dop853_traj",
                                    parts=MAPPERS + (DENSE,))
check("K with dop853 and a trajectory: the dense output compiled in, no mapper",
      len(found) == 1 and found[next(iter(found))] == {DENSE}, f"{found}")
if final_only and sampled:
    same_final_state("K with dop853: the same final states with the dense output and without",
                     final_only, sampled)

# A K in the energy trap's form (Σp²/2 + V(q) + k·z, no t) has fixed points alone (LaSalle), so
# its basin map leaves recurrences off by default (recurrence_plan.cpp, fixed_points_only), as
# the built-in double well's does: dop853's whole kernel holds the trap and its wells, no
# recurrences (recurrences on for such a K went unseen by every run's results).
mapped_dop853, found = run_in_fresh_cache(DOP853.replace("final_state = true", "basin = {}"),
                                          "well_k_dop853_map")
runner = [m for m in found.values() if m]
check("K in the trap's form with dop853, a basin map: the trap and its wells compiled in, no "
      "recurrences (fixed points only)", runner == [{"EnergyTrap<", "WellFinder<"}], f"{found}")

runs.finish()
