#!/usr/bin/env bash
# Benchmark of the main job: the 512 x 512 double-well basin map to t = 100 at h = 0.01
# (2.62e9 trajectory-steps), end to end (start-up, integration, HDF5 write), with and without
# the basin early stop, REPEATS times each; prints every run and the medians.
#   bash jobs/bench_basins.sh [REPEATS=5] [RANKS=2] [THREADS=1]
# Rates are nominal: grid points x steps / wall time, so the early-stop rate shows its gain.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repeats=${1:-5} ranks=${2:-2} threads=${3:-1}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=$threads
[[ -x build/contactsweep ]] || { cmake --preset release && cmake --build --preset release; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
traj_steps=$((512 * 512 * 10000))

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

for mode in full early_stop; do
  set_args=(--set measures.basin.early_stop=true)
  [[ $mode == full ]] && set_args=(--set measures.basin.early_stop=false)
  rates=()
  for ((i = 1; i <= repeats; i++)); do
    start=$(date +%s.%N)
    mpirun -np "$ranks" --bind-to core --map-by "slot:PE=$threads" build/contactsweep run \
      sweeps/basins_double_well.toml -o "$out/b.h5" --force --quiet "${set_args[@]}"
    end=$(date +%s.%N)
    rate=$(awk -v n="$traj_steps" -v a="$start" -v b="$end" 'BEGIN {printf "%.3e", n / (b - a)}')
    echo "$mode run $i: $(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.3f", b - a}') s, $rate traj-steps/s"
    rates+=("$rate")
  done
  echo "$mode: median $(printf '%s\n' "${rates[@]}" | median) traj-steps/s over $repeats runs ($ranks ranks x $threads threads)"
done
