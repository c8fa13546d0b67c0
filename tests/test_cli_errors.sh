#!/usr/bin/env bash
# Bad input at the command line, end to end: the real binary must exit with status 2, name the
# problem on stderr, and leave nothing behind (no output, no journal, no temporary file); an
# existing output must survive untouched. The parser's message corpus is in test_spec_parser.cpp;
# this checks what a user's shell sees, also under mpirun.
#   test_cli_errors.sh CONTACTSWEEP MPIEXEC
# Last line: "N passed, M failed, K skipped". Exit status: 1 if any failed; else 77 (CTest's
# SKIP_RETURN_CODE) if a case could not run here (the tmpfs case needs root; as root, CI, it must
# run); else 0.
set -uo pipefail
bin=$(realpath "$1") mpiexec=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'mountpoint -q "$work/small_disk" && umount "$work/small_disk"; rm -rf "$work"' EXIT

cat >"$work/good.toml" <<'EOF'
[scene]
name = "double_well"
[integrator]
h = 0.01
t_end = 1.0
[grid]
q_0 = { from = -3.0, to = 3.0, n = 64 }
p_0 = { from = -3.0, to = 3.0, n = 64 }
[measures]
basin = {}
final_state = true
EOF

passed=0 failed=0 skipped=0
# expect NAME STATUS FRAGMENT DIR -- COMMAND...: runs COMMAND in DIR; checks the exit status,
# that stderr contains FRAGMENT, and that DIR holds afterwards exactly what it held before.
expect() {
  local name=$1 status=$2 fragment=$3 dir=$4
  shift 5
  local before after rc=0
  before=$(cd "$dir" && find . -mindepth 1 -printf '%p %s %T@\n' | sort)
  (cd "$dir" && "$@") >"$work/stdout" 2>"$work/stderr" </dev/null || rc=$?
  after=$(cd "$dir" && find . -mindepth 1 -printf '%p %s %T@\n' | sort)
  local why=()
  ((rc == status)) || why+=("exit status $rc, expected $status")
  grep -qF -- "$fragment" "$work/stderr" || why+=("stderr lacks '$fragment'")
  [[ $before == "$after" ]] || why+=("the directory changed: $(diff <(echo "$before") <(echo "$after") | tr '\n' ' ')")
  if ((${#why[@]} == 0)); then
    echo "ok    $name"
    passed=$((passed + 1))
  else
    echo "FAIL  $name: ${why[*]}"
    sed 's/^/      stderr: /' "$work/stderr" | head -5
    failed=$((failed + 1))
  fi
}

spec_with() {  # a copy of good.toml with one line replaced: spec_with NAME SED-EXPRESSION
  sed "$2" "$work/good.toml" >"$work/$1.toml"
  echo "$work/$1.toml"
}

d=$work/out
mkdir -p "$d"
expect "unknown key, closest valid one suggested" 2 "did you mean 'integrator.method'" "$d" -- \
  "$bin" run "$(spec_with typo 's/^h = 0.01/metod = "rk4"/')"
expect "unknown scene, valid ones listed" 2 "coupled_oscillators" "$d" -- \
  "$bin" run "$(spec_with scene 's/double_well/double_wel/')"
expect "malformed TOML, with line and column" 2 "toml.toml:5:9: malformed TOML" "$d" -- \
  "$bin" run "$(spec_with toml 's/^t_end = 1.0/t_end = = 1.0/')"
expect "t_end not a whole number of steps" 2 "whole number of steps" "$d" -- \
  "$bin" run "$(spec_with steps 's/^t_end = 1.0/t_end = 1.005/')"
expect "--set without '='" 2 "integrator.h" "$d" -- "$bin" run "$work/good.toml" --set integrator.h
expect "--set of an unknown key" 2 "integrator.hh" "$d" -- "$bin" run "$work/good.toml" --set integrator.hh=0.1
expect "--set h = 0" 2 "integrator.h" "$d" -- "$bin" run "$work/good.toml" --set integrator.h=0
expect "the literature's s where z is meant" 2 "contactsweep calls it z (z = −s), so its value changes sign: did you mean 'initial.z'?" "$d" -- \
  "$bin" run "$work/good.toml" --set initial.s=1.0
expect "unreadable spec" 2 "missing.toml" "$d" -- "$bin" run "$work/missing.toml"
expect "unknown option" 2 "--frobnicate" "$d" -- "$bin" run "$work/good.toml" --frobnicate
expect "output directory is a file" 2 "not writable" "$d" -- \
  "$bin" run "$work/good.toml" -o "$work/good.toml/out.h5"
expect "results larger than the memory budget" 2 "of memory" "$d" -- \
  env CONTACTSWEEP_MEMORY_LIMIT=64K "$bin" run "$work/good.toml" -o grid.h5

# An existing output is never replaced without --force, and stays as it was.
"$bin" run "$work/good.toml" -o "$d/kept.h5" --quiet </dev/null || echo "FAIL  setup run"
expect "existing output without --force" 2 "pass --force" "$d" -- \
  "$bin" run "$work/good.toml" -o kept.h5
expect "--resume of another spec's output" 2 "not made by this spec" "$d" -- \
  "$bin" run "$work/good.toml" -o kept.h5 --resume --set integrator.t_end=2.0

# Under mpirun: the same status, the message once (rank 0 only), nothing written.
expect "bad input under mpirun -np 2" 2 "did you mean 'integrator.method'" "$d" -- \
  $mpiexec -np 2 "$bin" run "$work/typo.toml" -o mpi.h5
if (( $(grep -c "did you mean" "$work/stderr") != 1 )); then
  echo "FAIL  under mpirun the message should appear once, not $(grep -c "did you mean" "$work/stderr") times"
  failed=$((failed + 1))
fi

# MPMD launches whose ranks were given different arguments: rank 0 alone reads the spec and
# decides the start, but every rank parses with its own --set and journals beside its own output.
# Refused before any work (exit 2, nothing written, named once); they used to exit 1 after the
# other ranks' collectives parted ways ("another build or spec"), after rank 0 had journaled
# blocks ("the journal 'b.h5.journal' of this run is missing"), or crash (an empty -o on one rank).
expect "MPMD: ranks with different --set" 2 \
  "rank 1 (" "$d" -- \
  $mpiexec -np 1 "$bin" run "$work/good.toml" -o mpmd.h5 --set integrator.t_end=2.0 : \
  -np 1 "$bin" run "$work/good.toml" -o mpmd.h5
fragment="this rank was started with other overrides than rank 0 (no --set here, --set integrator.t_end=2.0 on rank 0); every rank of a run must be given the same --set"
if grep -qF -- "$fragment" "$work/stderr" && (($(grep -c "same --set" "$work/stderr") == 1)); then
  echo "ok    MPMD: ranks with different --set: named, once"
  passed=$((passed + 1))
else
  echo "FAIL  MPMD: ranks with different --set: stderr lacks '$fragment' (once)"
  failed=$((failed + 1))
fi
expect "MPMD: ranks with different -o" 2 \
  "rank 1 (" "$d" -- \
  $mpiexec -np 1 "$bin" run "$work/good.toml" -o a.h5 : -np 1 "$bin" run "$work/good.toml" -o b.h5
grep -qF "this rank would write 'b.h5' but rank 0 writes 'a.h5' (-o, or the spec's name with .h5 without -o); every rank of a run must be given the same -o" "$work/stderr" &&
  { echo "ok    MPMD: ranks with different -o: named"; passed=$((passed + 1)); } ||
  { echo "FAIL  MPMD: ranks with different -o: message"; failed=$((failed + 1)); }
cp "$work/good.toml" "$work/other_name.toml"
expect "MPMD: no -o and specs of different names (different default outputs)" 2 \
  "this rank would write 'other_name.h5' but rank 0 writes 'good.h5'" "$d" -- \
  $mpiexec -np 1 "$bin" run "$work/good.toml" : -np 1 "$bin" run "$work/other_name.toml"
expect "MPMD: an empty -o on one rank (was a crash, SIGSEGV)" 2 "-o: the output path is empty" "$d" -- \
  $mpiexec -np 1 "$bin" run "$work/good.toml" -o a.h5 : -np 1 "$bin" run "$work/good.toml" -o ''
mkdir -p "$d/w1" "$d/w2"
expect "MPMD: the same -o in two working directories" 2 \
  "this rank would write '$d/w2/w.h5' but rank 0 writes '$d/w1/w.h5'" "$d" -- \
  $mpiexec -np 1 -wdir "$d/w1" "$bin" run "$work/good.toml" -o w.h5 : \
  -np 1 -wdir "$d/w2" "$bin" run "$work/good.toml" -o w.h5
# The same file spelled two ways is one output: the run goes ahead.
mkdir -p "$work/spelled"
rc=0
(cd "$work/spelled" && $mpiexec -np 1 "$bin" run "$work/good.toml" -o same.h5 --quiet : \
  -np 1 "$bin" run "$work/good.toml" -o ./same.h5 --quiet </dev/null >"$work/stderr" 2>&1) || rc=$?
if ((rc == 0)) && [[ -s $work/spelled/same.h5 ]]; then
  echo "ok    MPMD: -o same.h5 and -o ./same.h5 are one output: exit 0, the file written"
  passed=$((passed + 1))
else
  echo "FAIL  MPMD: -o same.h5 and -o ./same.h5: exit $rc: $(tail -2 "$work/stderr")"
  failed=$((failed + 1))
fi

# Listings need no MPI (main.cpp parses before MPI starts) but still print once under mpirun,
# and a listing that cannot be written is a failure.
scenes_once=$($mpiexec -np 2 "$bin" scenes </dev/null 2>/dev/null | grep -c "(paper scene")
scenes_alone=$("$bin" scenes </dev/null | grep -c "(paper scene")
if ((scenes_alone > 0 && scenes_once == scenes_alone)); then
  echo "ok    scenes under mpirun -np 2: listed once"
  passed=$((passed + 1))
else
  echo "FAIL  scenes under mpirun -np 2: $scenes_once scene lines, $scenes_alone alone"
  failed=$((failed + 1))
fi
rc=0
"$bin" methods >/dev/full 2>/dev/null || rc=$?
if ((rc == 1)); then
  echo "ok    methods > /dev/full: exit 1"
  passed=$((passed + 1))
else
  echo "FAIL  methods > /dev/full: exit $rc, expected 1"
  failed=$((failed + 1))
fi

# An output larger than the free disk: a 64 KiB file system for a ~200 KiB file.
mkdir -p "$work/small_disk"
if ((EUID != 0)); then
  echo "skip  output larger than the free disk: mounting a small tmpfs needs root"
  skipped=$((skipped + 1))
elif mount -t tmpfs -o size=64k tmpfs "$work/small_disk" 2>"$work/stderr"; then
  expect "output larger than the free disk" 2 "free" "$work/small_disk" -- \
    "$bin" run "$work/good.toml" -o big.h5
else
  echo "FAIL  output larger than the free disk: root cannot mount a tmpfs: $(cat "$work/stderr")"
  failed=$((failed + 1))
fi

# ---- K written in the spec: each mistake is exit 2, named, nothing written (no kernel built) ---
# k_spec NAME SCENE-LINES [INTEGRATOR-LINES] [EXTRA-SECTIONS] [MEASURE-LINES]: a small K spec.
k_spec() {
  printf '[scene]\n%s\n[integrator]\n%s\nh = 0.01\nt_end = 1.0\n%s\n[measures]\nfinal_state = true\n%s\n' \
    "$2" "${3:-}" "${4:-}" "${5:-}" >"$work/k_$1.toml"
  echo "$work/k_$1.toml"
}
k_expect() {  # k_expect NAME FRAGMENT SPEC-ARGS...: the spec from k_spec is refused with FRAGMENT
  local name=$1 fragment=$2
  shift 2
  expect "K: $name" 2 "$fragment" "$d" -- "$bin" run "$(k_spec "${name// /_}" "$@")" -o k.h5
}
export CONTACTSWEEP_CACHE=$work/kernel_cache  # a refused spec must not even build a kernel
k_expect "unknown symbol, named with the valid names" \
  "symbol 'w' is neither a variable (q, p, z, t, pi) nor a parameter valued in [scene]: add w = <number>" \
  $'K = "p^2/2 + w*q^2/2 - gamma*z"\ngamma = 0.1'
k_expect "unknown symbol, 2 dof" "symbol 'k' is neither a variable (q1, q2, p1, p2, z, t, pi)" \
  'K = "p1^2/2 + p2^2/2 + k*q1*q2"'
k_expect "a [scene] key K does not use" \
  "scene.gamma is not a symbol of K, so it would have no effect; K's parameters: none" \
  $'K = "p^2/2 + q^2/2"\ngamma = 0.1'
k_expect "syntax error, with its column" "syntax error at column 16: expected a number, a name or '('" \
  'K = "p^2/2 + q^2/2 -* z"'
k_expect "unknown function" "unknown function 'sinn' at column 9; the functions are sin cos tan" \
  'K = "p^2/2 + sinn(q)"'
k_expect "q mixed with q1" "mixes p (column 1) with q1 (column 17)" 'K = "p^2/2 + q^2/2 + q1*p1"'
k_expect "both K and name" "[scene] has both name and K" $'K = "p^2/2 + q^2/2"\nname = "double_well"'
k_expect "t_start after t_end" "integrator.t_end = 1 is not after integrator.t_start = 2" \
  'K = "p^2/2 + q^2/2"' 't_start = 2.0'
k_expect "t_start equal to t_end" "integrator.t_end = 1 is not after integrator.t_start = 1" \
  'K = "p^2/2 + q^2/2"' 't_start = 1.0'
k_expect "empty K" "scene.K: is empty" 'K = ""'
k_expect "blank K" "scene.K: is empty" 'K = "   "'
k_expect "K without q or p" "has no position or momentum" 'K = "-0.1*z"'
k_expect "I" "I at column 9 is not allowed" 'K = "p^2/2 + I*q"'
k_expect "lambda" "lambda at column 9: lambda is the contact factor" $'K = "p^2/2 + lambda*q"\nlambda = 1.0'
k_expect "h" "h at column 9: h names the step-size axis" $'K = "p^2/2 + h*q"\nh = 1.0'
k_expect "== in K" "syntax error at column 12: '==' is a comparison" 'K = "p^2/2 + (q == 1)"'
k_expect "a^b^c" "syntax error at column 12: a^b^c is ambiguous" 'K = "p^2/2 + q^2^3"'
k_expect "unbalanced parenthesis" "syntax error at column 9: '(' is never closed" 'K = "p^2/2 + (q^2/2"'
k_expect "trailing operator" "syntax error at column 15: '+' at the end has no right operand" \
  'K = "p^2/2 + q^2/2 +"'
k_expect "constant beyond the double range (was exit 0 with 1.0)" \
  "scene.K: the constant exp(exp(exp(9))) is beyond the range of a double" 'K = "p^2/2 + exp(exp(exp(9)))*q"'
k_expect "constant that 5120 digits do not resolve" "cannot be evaluated to double precision" \
  'K = "p^2/2 + sin(exp(1e5))*q"'
k_expect "K beyond 64 kB (35 000 terms crashed: SIGSEGV)" "scene.K: is 69999 bytes long; K takes at most 65536" \
  "K = \"$(printf 'q+%.0s' {1..34999})q\""
k_expect "K not a string" "scene.K: expected a string (in quotes), got a float 3.0" 'K = 3.0'
k_expect "a splitting on a K that does not split" \
  'method "contact_splitting4" needs K = sum of p_i^2/2 + V(q, t) + c(t)*z' \
  'K = "p^4/4 + q^2/2 - z"' 'method = "contact_splitting4"'
k_expect "basin period not whole steps" \
  "measures.basin.period = 0.0333: the stroboscopic map needs a whole number of steps per period" \
  'K = "p^2/2 + q^2/2 - 0.1*z - cos(t)*q"' '' '' 'basin = { period = 0.0333 }'
k_expect "basin angle of an unknown variable" \
  "measures.basin.angles.theta: 'theta' is not a position or momentum of scene 'custom' (q, p)" \
  'K = "p^2/2 + q^2/2 - 0.1*z"' '' '' 'basin = { angles = { theta = 6.28 } }'
k_expect "basin cycles without a period" \
  "measures.basin.max_period: cycles are looked for on the stroboscopic map only" \
  'K = "p^2/2 + q^2/2 - 0.1*z"' '' '' 'basin = { max_period = 2 }'
k_expect "basin tolerance zero" "expected a distance > 0 (max norm over q and p)" \
  'K = "p^2/2 + q^2/2 - 0.1*z"' '' '' 'basin = { tolerance = 0.0 }'
k_expect "sync on a one-dof K" "measures.sync: scene 'custom' does not support 'sync'" \
  'K = "p^2/2 + q^2/2 - 0.1*z"' '' '' 'sync = {}'
k_expect "sync of a degree of freedom K does not have" \
  "measures.sync.dof[1] = 3: expected a degree of freedom of scene 'custom', from 1 to 2" \
  'K = "p1^2/2 + p2^2/2 + q1^2/2 + q2^2/2 - 0.1*z"' '' '' 'sync = { dof = [1, 3] }'
k_expect "an initial variable K does not have" "unknown key 'initial.q2'" \
  'K = "p^2/2 + q^2/2"' '' $'[initial]\nq2 = 1.0'
k_expect "an initial momentum beyond K's dof" "unknown key 'initial.p3'" \
  'K = "p1^2/2 + p2^2/2 + q1^2/2 + q2^2/2"' '' $'[initial]\np3 = 1.0'
k_expect "a parameter valued with a string" 'scene.w: expected a number, got a string "one"' \
  $'K = "p^2/2 + w*q^2/2"\nw = "one"'
k_expect "t_start infinite" "integrator.t_start = inf: expected a finite number" \
  'K = "p^2/2 + q^2/2"' 't_start = inf'
k_expect "not whole steps from t_start" "integrator.t_end - t_start = 0.995 is not a whole number of steps" \
  'K = "p^2/2 + q^2/2"' 't_start = 0.005'
k_expect "empty label" "scene.label is empty" $'K = "p^2/2 + q^2/2"\nlabel = ""'
k_expect "a grid axis over a symbol not in K" "unknown key 'grid.gamma'; valid keys in [grid]: w, h" \
  $'K = "p^2/2 + w*q^2/2"\nw = 1.0' '' $'[grid]\ngamma = { values = [0.1, 0.2] }'
expect "K: --set of a symbol not in K" 2 "--set scene.gamma=0.2: scene.gamma is not a symbol of K" \
  "$d" -- "$bin" run "$(k_spec set_unknown $'K = "p^2/2 + w*q^2/2"\nw = 1.0')" -o k.h5 \
  --set scene.gamma=0.2
expect "K: unknown symbol under mpirun" 2 "symbol 'w' is neither a variable" "$d" -- \
  $mpiexec -np 2 "$bin" run "$work/k_unknown_symbol,_named_with_the_valid_names.toml" -o k.h5
# Measures as formulas (observe, observe_window, stop): K's rules, and nothing built either.
k_expect "observe: unknown symbol" \
  "measures.observe.E: 'p^2/2 + w*q^2/2' reads 'w', which is not a symbol of scene" \
  'K = "p^2/2 + q^2/2"' '' '' 'observe = { E = "p^2/2 + w*q^2/2" }'
k_expect "observe: a name of a dataset the file has" "measures.observe.H: 'H' would name the datasets" \
  'K = "p^2/2 + q^2/2"' '' '' 'observe = { H = "p^2/2" }'
k_expect "observe: a state variable's name" "measures.observe.q: 'q' would name the datasets" \
  'K = "p^2/2 + q^2/2"' '' '' 'observe = { q = "p" }'
k_expect "observe: syntax error, with its column" "measures.observe.E: 'p^2 + * q' syntax error at column 7" \
  'K = "p^2/2 + q^2/2"' '' '' 'observe = { E = "p^2 + * q" }'
k_expect "observe_window outside the run" \
  "measures.observe_window = { from = 0.5, to = 2 }: expected 0 <= from <= to <= t_end = 1" \
  'K = "p^2/2 + q^2/2"' '' '' $'observe = { E = "p^2" }\nobserve_window = { from = 0.5, to = 2.0 }'
expect "observe_window: --set of an end outside the run names the argument" 2 \
  "--set measures.observe_window.to=3: measures.observe_window = { from = 0.5, to = 3 }: expected 0 <= from <= to <= t_end = 1" \
  "$d" -- "$bin" run "$(k_spec window_set 'K = "p^2/2 + q^2/2"' '' '' $'observe = { E = "p^2" }\nobserve_window = { from = 0.5, to = 1.0 }')" \
  -o k.h5 --set measures.observe_window.to=3
k_expect "observe_window holding no sample" \
  "holds no sample: samples come every 0.5 time units (trajectory.every = 50 steps of h = 0.01)" \
  'K = "p^2/2 + q^2/2"' '' '' $'trajectory = { every = 50 }\nobserve = { E = "p^2" }\nobserve_window = { from = 0.6, to = 0.9 }'
k_expect "observe_window between two steps, no trajectory" \
  "holds no sample: samples come every 0.01 time units (every step of h = 0.01, no trajectory)" \
  'K = "p^2/2 + q^2/2"' '' '' $'observe = { E = "p^2" }\nobserve_window = { from = 0.601, to = 0.605 }'
k_expect "stop: not a comparison" "measures.stop.when: 'q^2 + p^2' at column 1 is not a comparison" \
  'K = "p^2/2 + q^2/2"' '' '' 'stop = { when = "q^2 + p^2" }'
k_expect "stop: equality" "measures.stop.when: '==' at column 3: a condition compares with <, <=, > or >=" \
  'K = "p^2/2 + q^2/2"' '' '' 'stop = { when = "q == 1" }'
k_expect "stop: dangling and" "measures.stop.when: 'and' / 'or' without a comparison" \
  'K = "p^2/2 + q^2/2"' '' '' 'stop = { when = "q > 1 and" }'
k_expect "stop: unknown symbol" "measures.stop.when: 'r' reads 'r', which is not a symbol" \
  'K = "p^2/2 + q^2/2"' '' '' 'stop = { when = "q > r" }'
expect "built-in scene: observe of a parameter it lacks" 2 \
  "measures.observe.E: 'omega*q' reads 'omega', which is not a symbol of scene 'double_well'" "$d" -- \
  "$bin" run "$(spec_with observe_builtin 's/^final_state = true/final_state = true\nobserve = { E = "omega*q" }/')" -o obs.h5
expect "built-in scene: stop under mpirun, unknown symbol" 2 "measures.stop.when" "$d" -- \
  $mpiexec -np 2 "$bin" run "$(spec_with stop_builtin 's/^final_state = true/final_state = true\nstop = { when = "q1 > 0" }/')" -o obs.h5
# The start is decided before a kernel is built: a K's output finished (its kernel built into
# another cache), then asked for again without --force, or resumed with another spec or a new
# formula, is refused at once; it used to compile the new kernel first (1.5 s and more).
k_done=$(k_spec finished 'K = "p^2/2 + q^2/2 - 0.1*z"' '' '' 'observe = { E = "p^2/2 + q^2/2" }')
CONTACTSWEEP_CACHE=$work/setup_cache "$bin" run "$k_done" -o "$d/k_done.h5" --quiet </dev/null ||
  echo "FAIL  setup run of a K"
mkdir -m 700 "$d/k_cache"  # each case's own: a kernel built into it changes the directory
expect "K: existing output without --force, before any kernel is built" 2 "pass --force" "$d" -- \
  env CONTACTSWEEP_CACHE="$d/k_cache" "$bin" run "$k_done" -o k_done.h5
expect "K: --resume with another h, before any kernel is built" 2 "not made by this spec" "$d" -- \
  env CONTACTSWEEP_CACHE="$d/k_cache" "$bin" run "$k_done" -o k_done.h5 --resume --set integrator.h=0.005
expect "K: --resume with a changed formula, before any kernel is built" 2 "not made by this spec" "$d" -- \
  env CONTACTSWEEP_CACHE="$d/k_cache" "$bin" run "$k_done" -o k_done.h5 --resume --set 'measures.observe.E="p^2/2"'
# The memory and disk checks refuse a run before any kernel is built too (it used to compile
# the kernel first, 3 s, and leave it in the cache).
expect "K: results larger than the memory budget, before any kernel is built" 2 "of memory" "$d" -- \
  env CONTACTSWEEP_CACHE="$d/k_cache" CONTACTSWEEP_MEMORY_LIMIT=1 "$bin" run "$k_done" -o k_memory.h5
if [[ -z $(ls "$CONTACTSWEEP_CACHE" 2>/dev/null) ]]; then
  echo "ok    K: no refused spec built a kernel"
  passed=$((passed + 1))
else
  echo "FAIL  K: a refused spec built a kernel: $(ls "$CONTACTSWEEP_CACHE")"
  failed=$((failed + 1))
fi
unset CONTACTSWEEP_CACHE

# The harness itself: a good run exits 0 and its file appears (so 'nothing written' above means
# something).
rc=0
(cd "$d" && "$bin" run "$work/good.toml" -o fresh.h5 --quiet </dev/null) || rc=$?
if ((rc == 0)) && [[ -s $d/fresh.h5 ]]; then
  echo "ok    a good run exits 0 and writes its file"
  passed=$((passed + 1))
else
  echo "FAIL  a good run: exit $rc, file $(ls -l "$d/fresh.h5" 2>&1)"
  failed=$((failed + 1))
fi

echo "$passed passed, $failed failed, $skipped skipped"
((failed == 0)) || exit 1
((skipped == 0)) || exit 77
