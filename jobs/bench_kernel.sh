#!/usr/bin/env bash
# The kernel benchmark (tests/bench/kernel_bench.cpp): every scene x method x carried state on
# every ISA path this CPU runs, REPEATS repetitions each, one core; prints the medians as a table
# (ns per lane-step, lane-steps/s, fraction of the FMA roofline against the FMA peak measured
# right before each run, so that both see the same clock; medians over the repetitions). Two
# rooflines: "all ops" counts adds as FMA-unit work (Intel's 512-bit path, where they share the
# units); "mul+fma" counts multiplies and FMAs alone (Zen 4 and 5, where adds have pipes of their
# own). The true limit of a CPU lies between the two.
#   bash jobs/bench_kernel.sh [REPEATS=5] [FILTER=.]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repeats=${1:-5} filter=${2:-.}
[[ -x build/tests/bench/kernel_bench ]] || { cmake --preset release && cmake --build --preset release --target kernel_bench; }
json=$(mktemp)
source jobs/machine_facts.sh
trap 'rm -f "$json"; machine_load_at_end' EXIT
build/tests/bench/kernel_bench --benchmark_filter="$filter" --benchmark_repetitions="$repeats" \
  --benchmark_report_aggregates_only=true --benchmark_min_time=0.2 --benchmark_format=json \
  >"$json" 2>/dev/null
/usr/bin/python3 - "$json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
print(f"{'case':50} {'ns/lane-step':>12} {'lane-steps/s':>13} {'all ops':>8} {'mul+fma':>8}")
for b in report["benchmarks"]:
    if b.get("aggregate_name") != "median":
        continue
    if b["run_name"].startswith("fma_peak/"):
        print(f"{b['run_name']:50} peak {b['peak'] * 1e-9:.1f} G FMA-pipe ops/s per core")
        continue
    rate = b["lane_steps/s"]
    roof = lambda key: f"{100 * b[key]:.0f} %" if key in b else "-"
    print(f"{b['run_name']:50} {1e9 / rate:12.3f} {rate:13.3e} {roof('roofline'):>8} "
          f"{roof('roofline_fma_units'):>8}")
PY
