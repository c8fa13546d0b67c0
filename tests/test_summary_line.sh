#!/usr/bin/env bash
# The run's summary line says what was integrated: a fixed-step run whose lanes all reach t_end
# adds nothing to the nominal rate; an adaptive run's lane-steps are its attempts, counted
# against the nominal t_end / h and never called lanes that "stopped early" (none did: no
# measure here stops a lane). Built-in scene, so no kernel is compiled.
#   test_summary_line.sh CONTACTSWEEP
set -uo pipefail
bin=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail=0
check() { if eval "$2"; then echo "ok    $1"; else echo "FAIL  $1"; fail=1; fi; }

cat >spec.toml <<'SPEC'
[scene]
name = "double_well"
[integrator]
method = "rk4"
h = 0.01
t_end = 10.0
[grid]
q_0 = { from = -2.0, to = 2.0, n = 8 }
[measures]
final_state = true
SPEC
"$bin" run spec.toml -o fixed.h5 2>fixed.log
check "fixed step, every lane to t_end: exit 0" "[[ $? == 0 ]]"
check "fixed step, every lane to t_end: no lane-steps clause" \
  "! grep -q 'lane-steps integrated' fixed.log"

# dop853 at rtol 1e-6 over t = 10 takes far fewer attempts than the nominal 1000 steps a lane.
"$bin" run spec.toml -o adaptive.h5 --set integrator.method='"dop853"' \
  --set integrator.rtol=1e-6 --set integrator.atol=1e-6 2>adaptive.log
check "dop853: exit 0" "[[ $? == 0 ]]"
line=$(grep 'wrote adaptive.h5' adaptive.log)
check "dop853: the attempts are counted against the nominal t_end / h" \
  "grep -q \"lane-steps integrated ([0-9]* % of the nominal t_end / h: an adaptive method's attempts)\" <<<\"\$line\""
check "dop853: no lane is said to have stopped early" "! grep -q 'stopped early' <<<\"\$line\""
# The share is the count over 8 lanes x 1000 nominal steps, as printed (3 digits, rounded %).
/usr/bin/python3 - "$line" <<'PY' || fail=1
import re, sys
m = re.search(r"; ([0-9.e+]+) lane-steps integrated \(([0-9]+) % of the nominal", sys.argv[1])
count, share = float(m.group(1)), int(m.group(2))
assert 8 <= count < 8 * 1000, count  # at least one attempt a lane, fewer than the nominal steps
assert abs(100 * count / 8000 - share) <= 0.5 + 100 * 0.0005 * count / 8000, (count, share)
print(f"ok    dop853: {count:g} attempts, {share} % of 8 x 1000 nominal steps")
PY
exit $fail
