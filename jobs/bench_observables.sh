#!/usr/bin/env bash
# What measures as formulas cost (docs/observables.md): user CPU of a double-well map
# in variants run interleaved, REPEATS rounds, medians printed. One process, OMP threads as given.
#   bash jobs/bench_observables.sh [REPEATS=7] [N=256] [THREADS=1]
# Variants (each an N x N map over (q_0, p_0) to t = 100, h = 0.01, final_state q unless said):
#   builtin        the built-in scene (ahead-of-time kernel)
#   k              the same K written in the spec (run-time kernel): the baseline of the rest
#   k_observe      + observe E = p^2/2 + V (final_E only: once per lane)
#   k_window       + observe_window over [50, 100] (no trajectory: E every step of the window)
#   k_stop_never   + stop when q > 100 (never holds: the condition every step, the snapshots)
#   k_stop_half    + stop when t > 50 (every lane stops at t = 50.01, the first step past 50)
#   k_never_half   t_end = 50 with the never-holding stop: what k_stop_half costs if a stopped
#                  lane costs nothing after its stop (both check the condition at every step)
#   k_half         t_end = 50, no stop
#   basin / basin_observe   the basin map (early stop) without / with observe E
# The kernels are built once before the rounds (a private cache), so no build is timed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repeats=${1:-7} n=${2:-256} threads=${3:-1}
export OMP_NUM_THREADS=$threads
work=$(mktemp -d)
source jobs/machine_facts.sh
trap 'rm -rf "$work"; machine_load_at_end' EXIT
export CONTACTSWEEP_CACHE=$work/cache

spec() {  # spec NAME SCENE-LINES MEASURE-LINES [T_END]
  printf '[scene]\n%s\n[initial]\nz = 1.0\n[integrator]\nmethod = "hybrid_leapfrog"\nh = 0.01\nt_end = %s\n[grid]\nq_0 = { from = -3.0, to = 3.0, n = %s }\np_0 = { from = -3.0, to = 3.0, n = %s }\n[measures]\n%s\n' \
    "$2" "${4:-100.0}" "$n" "$n" "$3" >"$work/$1.toml"
}
builtin='name = "double_well"'
k=$'K = "p^2/2 + (q^2 - a*a)^2/2 - gamma*z"\na = 1.0\ngamma = 0.1'
final='final_state = { vars = ["q"] }'
E='observe = { E = "p^2/2 + (q^2 - a*a)^2/2" }'
spec builtin "$builtin" "$final"
spec k "$k" "$final"
spec k_observe "$k" "$final"$'\n'"$E"
spec k_window "$k" "$final"$'\n'"$E"$'\nobserve_window = { from = 50.0, to = 100.0 }'
spec k_stop_never "$k" "$final"$'\nstop = { when = "q > 100" }'
spec k_stop_half "$k" "$final"$'\nstop = { when = "t > 50" }'
spec k_never_half "$k" "$final"$'\nstop = { when = "q > 100" }' 50.0
spec k_half "$k" "$final" 50.0
spec basin "$builtin" $'basin = {}\n'"$final"
spec basin_observe "$builtin" $'basin = {}\n'"$final"$'\n'"$E"
variants=(builtin k k_observe k_window k_stop_never k_stop_half k_never_half k_half basin basin_observe)

for v in "${variants[@]}"; do build/contactsweep run "$work/$v.toml" -o "$work/$v.h5" --force --quiet; done
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
declare -A times
for ((i = 1; i <= repeats; i++)); do
  for v in "${variants[@]}"; do
    t=$( { /usr/bin/time -f "%U" build/contactsweep run "$work/$v.toml" -o "$work/$v.h5" --force --quiet; } 2>&1 | tail -n 1)
    times[$v]+="$t "
    echo "round $i $v: $t s user"
  done
done
echo "medians over $repeats interleaved rounds ($n x $n, $threads thread(s)), user CPU:"
for v in "${variants[@]}"; do
  printf '  %-14s %s s\n' "$v" "$(tr ' ' '\n' <<<"${times[$v]}" | grep . | median)"
done
