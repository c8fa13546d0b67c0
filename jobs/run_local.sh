#!/usr/bin/env bash
# The main job on one 2-core machine: builds if needed, runs the paper's figure specs (and the
# basin / sync maps when their specs exist) into out/, then draws the PNGs into out/figures/.
#   bash jobs/run_local.sh
#
# Binding: 2 MPI ranks x 1 OpenMP thread, each rank bound to its own core (--bind-to core,
# OMP_NUM_THREADS=1). Every lane of a sweep is independent, so ranks scale as well as threads
# here, and pinning keeps a rank from migrating between the two cores mid-run.
# Alternative with the same 2 cores: one rank, two threads on two cores
#   OMP_NUM_THREADS=2 OMP_PLACES=cores OMP_PROC_BIND=close \
#     mpirun -np 1 --map-by slot:PE=2 build/contactsweep run SPEC -o OUT --force
# (--map-by slot:PE=2 gives the rank both cores; plain --bind-to core would squeeze both threads
# onto one core). Results are identical either way: the output does not depend on the split.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Open MPI refuses to run as root (containers, CI) without both of these.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1
mpirun=(mpirun -np 2 --bind-to core)

bash .ci/install-deps.sh
[[ -f build/CMakeCache.txt ]] || cmake --preset release
cmake --build --preset release --target contactsweep   # the program only: tests build with .ci/test

mkdir -p out/figures
run() {  # run NAME: sweeps/NAME.toml -> out/NAME.h5
  echo "== $1"
  "${mpirun[@]}" build/contactsweep run "sweeps/$1.toml" -o "out/$1.h5" --force
}
for name in paper_fig1a paper_fig1b paper_fig2 paper_fig3; do
  run "$name"
done
for name in basins_double_well sync_g_gamma lyapunov_duffing; do  # the maps, once their specs are written
  if [[ -f sweeps/$name.toml ]]; then run "$name"; else echo "== $name: no sweeps/$name.toml, skipped"; fi
done

basins=(basins_magnetic_pendulum basins_magnetic_continuation basins_forced_duffing basins_spin_orbit)
for name in "${basins[@]}"; do run "$name"; done  # basins of any system (K in the spec)

/usr/bin/python3 src/post/plot_paper_figures.py --in out --out out/figures
/usr/bin/python3 src/post/plot_maps.py --in out --out out/figures
files=()
for name in "${basins[@]}"; do files+=("out/$name.h5"); done
/usr/bin/python3 src/post/plot_basins.py out/figures "${files[@]}"
run escape_henon_heiles  # exit basins and escape times (measures.stop, docs/observables.md)
/usr/bin/python3 src/post/plot_escape.py out/figures out/escape_henon_heiles.h5

# Attractors of every kind (docs/showcases.md): a limit cycle, the forced Duffing written
# autonomously (compared with basins_forced_duffing above), a strange attractor beside a periodic
# orbit, Lorenz, an orbit diagram. Wall time on 2 shared cores, kernels
# cached: ~6, ~32, ~7, ~4, ~3 s.
showcases=(basins_van_der_pol basins_forced_duffing_autonomous basins_forced_duffing_chaos
           basins_lorenz orbit_diagram_duffing)
for name in "${showcases[@]}"; do run "$name"; done
/usr/bin/python3 src/post/plot_showcases.py --in out --out out/figures
echo "done: results in out/, figures in out/figures/"
