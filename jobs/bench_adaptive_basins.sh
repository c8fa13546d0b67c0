#!/usr/bin/env bash
# The basin-accuracy table of docs/methods.md: dop853 against rk4, each at the settings that
# bracket zero wrong cells, on the double well (sweeps/basins_double_well.toml, 512 x 512,
# t = 100) and the magnetic pendulum (sweeps/basins_magnetic_pendulum.toml, 512 x 512,
# t = 200), early stop as in the specs. Wrong cells: against rk4 at h = 0.0025 (checked against
# dop853 at rtol = 1e-12). Runs interleaved (every setting once per round, REPEATS rounds), the
# program's own time (set-up, integration, write), THREADS OpenMP threads, one process; prints
# each setting's wrong cells, attempts or steps, and the median time with its range.
#   bash jobs/bench_adaptive_basins.sh [REPEATS=5] [THREADS=2]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repeats=${1:-5} threads=${2:-2}
[[ -x build/contactsweep ]] || { cmake --preset release && cmake --build --preset release; }
out=$(mktemp -d)
source jobs/machine_facts.sh
trap 'rm -rf "$out"; machine_load_at_end' EXIT

run() {  # NAME SPEC SETS...: the run's summary line
  local name=$1 spec=$2
  shift 2
  OMP_NUM_THREADS=$threads build/contactsweep run "$spec" -o "$out/$name.h5" --force "$@" 2>&1 |
    grep "wrote"
}

declare -A spec grid
spec[dw]=sweeps/basins_double_well.toml grid[dw]="--set grid.q_0.n=512 --set grid.p_0.n=512"
spec[mp]=sweeps/basins_magnetic_pendulum.toml grid[mp]="--set grid.q1_0.n=512 --set grid.q2_0.n=512"
rk4() { echo "--set integrator.method=\"rk4\" --set integrator.h=$1"; }
dop() { echo "--set integrator.method=\"dop853\" --set integrator.rtol=$1 --set integrator.atol=$1"; }
declare -A settings
settings[dw]="rk4:0.025 rk4:0.0125 dop853:1e-6 dop853:1e-7 dop853:1e-8"
settings[mp]="rk4:0.05 rk4:0.025 rk4:0.0125 dop853:1e-5 dop853:1e-6 dop853:1e-7 dop853:1e-8"

for map in dw mp; do
  # shellcheck disable=SC2046
  run "${map}_ref" "${spec[$map]}" ${grid[$map]} $(rk4 0.0025) >/dev/null
  # shellcheck disable=SC2046
  run "${map}_ref_dop" "${spec[$map]}" ${grid[$map]} $(dop 1e-12) >/dev/null
done
for ((r = 1; r <= repeats; r++)); do
  for map in dw mp; do
    for s in ${settings[$map]}; do
      method=${s%%:*} value=${s#*:}
      name="${map}_${method}_${value}"
      # shellcheck disable=SC2046
      line=$(run "$name" "${spec[$map]}" ${grid[$map]} $($([[ $method == rk4 ]] && echo rk4 || echo dop) "$value"))
      echo "$name $(sed -n 's/.* in \([0-9.]*\) s,.*/\1/p' <<<"$line") $(sed -n 's/.*; \([0-9.e+]*\) lane-steps integrated.*/\1/p' <<<"$line")" >>"$out/times"
    done
  done
done
/usr/bin/python3 - "$out" "$repeats" <<'EOF'
import sys
from collections import defaultdict

import h5py
import numpy as np

out, repeats = sys.argv[1], int(sys.argv[2])
times, steps = defaultdict(list), {}
for line in open(f"{out}/times"):
    name, t, *n = line.split()
    times[name].append(float(t))
    steps[name] = n[0] if n else "all"
basin = lambda name: h5py.File(f"{out}/{name}.h5")["basin"][...]
for m, title in (("dw", "double well 512 x 512, t = 100"), ("mp", "magnetic pendulum 512 x 512, t = 200")):
    ref = basin(f"{m}_ref")
    print(f"\n{title}: reference rk4 h = 0.0025; dop853 at rtol 1e-12 differs from it in "
          f"{int((basin(f'{m}_ref_dop') != ref).sum())} cells")
    print(f"{'setting':24s}{'wrong cells':>12s}{'lane-steps':>12s}{'median s':>10s}{'range':>16s}")
    for name in [k for k in times if k.startswith(m + "_")]:
        t = np.array(times[name])
        print(f"{name[3:]:24s}{int((basin(name) != ref).sum()):12d}{steps[name]:>12s}"
              f"{np.median(t):10.3f}{f'{t.min():.3f} - {t.max():.3f}':>16s}")
print(f"\n{repeats} interleaved rounds")
EOF
