#!/usr/bin/env bash
# What finding attractors costs (docs/performance.md, "Attractors"): user CPU of a basin map
# whose attractor is a limit cycle (van der Pol), a strange attractor beside a cycle (the
# chaotic forced Duffing) and fixed points (the built-in double well's energy trap), each
#   integrate   the same grid and run with final_state only (no mapper at all),
#   map_full    basin = {...} with early_stop = false: every lane to t_end, so the difference
#               from `integrate` is the mappers' bookkeeping alone,
#   map         the map as a user runs it (lanes stop once settled).
# Interleaved rounds, medians; kernels built before the rounds (a private cache).
#   bash jobs/bench_attractors.sh [REPEATS=5] [N=64] [THREADS=1]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repeats=${1:-5} n=${2:-64} threads=${3:-1}
export OMP_NUM_THREADS=$threads
[[ -x build/contactsweep ]] || { cmake --preset release && cmake --build --preset release; }
work=$(mktemp -d)
source jobs/machine_facts.sh
trap 'rm -rf "$work"; machine_load_at_end' EXIT
export CONTACTSWEEP_CACHE=$work/cache

declare -A spec=([limit_cycle]=sweeps/basins_van_der_pol.toml
                 [chaotic]=sweeps/basins_forced_duffing_chaos.toml
                 [fixed_points]=sweeps/basins_double_well.toml)
cases=(limit_cycle chaotic fixed_points)
axes() { sed -n 's/^\([a-z0-9_]*\) = { from.*/\1/p' "$1"; }
variants=()
for c in "${cases[@]}"; do
  grid=() cells=$n
  [[ $c == fixed_points ]] && cells=$((4 * n))  # 10⁴ steps a lane against 4–5·10⁴: 16x the lanes
  for a in $(axes "${spec[$c]}"); do grid+=(--set "grid.$a.n=$cells"); done
  # integrate: the basin measure dropped from the spec's text, the final value of the first
  # axis' variable kept (as the maps carry: q and p, no z or ln λ, which final_state = true adds)
  first=$(axes "${spec[$c]}" | head -n 1)
  grep -v '^basin = \|^final_state = ' "${spec[$c]}" |
    sed "s/^\[measures\]\$/[measures]\nfinal_state = { vars = [\"${first%_0}\"] }/" >"$work/$c.integrate.toml"
  args_integrate=("$work/$c.integrate.toml" "${grid[@]}")
  args_map_full=("${spec[$c]}" "${grid[@]}" --set measures.basin.early_stop=false)
  args_map=("${spec[$c]}" "${grid[@]}")
  for v in integrate map_full map; do
    declare -n args="args_$v"
    printf '%s\0' "${args[@]}" >"$work/$c.$v.args"
    variants+=("$c.$v")
  done
done

run() { local -a a; mapfile -d '' a <"$work/$1.args"; build/contactsweep run "${a[@]}" -o "$work/$1.h5" --force --quiet; }
for v in "${variants[@]}"; do run "$v"; done  # builds the kernels, checks every variant runs
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
declare -A times
for ((i = 1; i <= repeats; i++)); do
  for v in "${variants[@]}"; do
    t=$( { /usr/bin/time -f "%U" bash -c "$(declare -f run); work=$work; run $v"; } 2>&1 | tail -n 1)
    times[$v]+="$t "
  done
done
echo "medians over $repeats interleaved rounds (${n}² cells, fixed points $((4 * n))², $threads thread(s)), user CPU:"
for c in "${cases[@]}"; do
  i=$(tr ' ' '\n' <<<"${times[$c.integrate]}" | grep . | median)
  f=$(tr ' ' '\n' <<<"${times[$c.map_full]}" | grep . | median)
  m=$(tr ' ' '\n' <<<"${times[$c.map]}" | grep . | median)
  awk -v c="$c" -v i="$i" -v f="$f" -v m="$m" 'BEGIN {
    printf "  %-13s integrate %.3f s, map to t_end %.3f s (bookkeeping %.0f %% of it), map with early stop %.3f s (%.2fx integrate)\n",
           c, i, f, 100 * (f - i) / f, m, m / i }'
done
