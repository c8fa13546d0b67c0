#!/usr/bin/env bash
# Progress lines come on time whatever the blocks: 8 lanes over many steps are one block, and
# its lines must still come, each further on than the last (issue 22).
#   test_progress.sh CONTACTSWEEP T_END   (a run of ~2 s: the sanitizer build passes a shorter one)
set -uo pipefail
bin=$(realpath "$1") t_end=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cat >long.toml <<'SPEC'
[scene]
name = "damped_oscillator"
[integrator]
h = 0.01
t_end = 1.0
[grid]
q_0 = { from = -1.0, to = 1.0, n = 8 }
[measures]
final_state = true
SPEC
CONTACTSWEEP_PROGRESS_SECONDS=0.1 OMP_NUM_THREADS=1 "$bin" run long.toml -o long.h5 --set integrator.t_end="$t_end" 2>stderr
rc=$?
percents=$(grep -o '^contactsweep: *[0-9.]*% done' stderr | grep -o '[0-9.]*%' | tr -d '%')
echo "exit $rc; progress lines: $(echo $percents)"
/usr/bin/python3 - "$rc" $percents <<'PY'
import sys
rc, p = int(sys.argv[1]), [float(x) for x in sys.argv[2:]]
assert rc == 0, f"exit {rc}"
# 8 lanes are one block: without progress inside blocks no line comes at all.
assert len(p) >= 2, f"{len(p)} progress lines from a one-block run"
assert 0.0 < p[0] < 100.0 and p[-1] <= 100.0, p
assert all(b >= a for a, b in zip(p, p[1:])) and p[-1] > p[0], f"not increasing: {p}"
print("ok    progress inside a one-block run:", len(p), "lines,", p[0], "->", p[-1], "%")
PY
