#!/usr/bin/env bash
# Benchmark of the main job: the 512 x 512 double-well basin map to t = 100 at h = 0.01
# (2.62e9 trajectory-steps), end to end (start-up, integration, HDF5 write), with and without
# the basin early stop, REPEATS times each; prints every run and the medians.
#   bash jobs/bench_basins.sh [REPEATS=5] [RANKS=2] [THREADS=1]
# RANKS=0 runs one process without a launcher (THREADS OpenMP threads, bound to cores): the
# layout for one node, which skips mpirun's own start (~0.3 s here) and never starts MPI.
# Rates are nominal: grid points x steps / time, so the early-stop rate shows its gain. Two
# times per run: "wall" is the whole command (mpirun's process launch ~0.3 s included);
# "run" is the program's own end-to-end time (set-up after spec parsing, integration, HDF5 write and
# commit), as it reports it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repeats=${1:-5} ranks=${2:-2} threads=${3:-1}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=$threads
[[ -x build/contactsweep ]] || { cmake --preset release && cmake --build --preset release; }
out=$(mktemp -d)
source jobs/machine_facts.sh
trap 'rm -rf "$out"; machine_load_at_end' EXIT
traj_steps=$((512 * 512 * 10000))

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

for mode in full early_stop; do
  set_args=(--set measures.basin.early_stop=true)
  [[ $mode == full ]] && set_args=(--set measures.basin.early_stop=false)
  wall_rates=() run_rates=()
  for ((i = 1; i <= repeats; i++)); do
    start=$(date +%s.%N)
    launcher=(mpirun -np "$ranks" --bind-to core --map-by "slot:PE=$threads")
    ((ranks == 0)) && launcher=(env OMP_PROC_BIND=close OMP_PLACES=cores)
    report=$("${launcher[@]}" build/contactsweep \
      run sweeps/basins_double_well.toml -o "$out/b.h5" --force "${set_args[@]}" 2>&1 | tail -n 1)
    end=$(date +%s.%N)
    wall=$(awk -v n="$traj_steps" -v a="$start" -v b="$end" 'BEGIN {printf "%.3e", n / (b - a)}')
    run=$(sed -n 's/.* in \([0-9.]*\) s,.*/\1/p' <<<"$report")
    run_rate=$(awk -v n="$traj_steps" -v t="$run" 'BEGIN {printf "%.3e", n / t}')
    echo "$mode $i: wall $(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.3f", b - a}') s ($wall traj-steps/s), run $run s ($run_rate traj-steps/s)"
    wall_rates+=("$wall") run_rates+=("$run_rate")
  done
  echo "$mode: median run $(printf '%s\n' "${run_rates[@]}" | median), wall $(printf '%s\n' "${wall_rates[@]}" | median) traj-steps/s over $repeats runs ($( ((ranks == 0)) && echo "1 process, no launcher" || echo "$ranks ranks") x $threads threads)"
done
