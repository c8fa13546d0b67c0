#!/usr/bin/env bash
# K written in the spec, end to end through the run-time compiler: the paper's scenes written as
# K against the built-ins, time-dependent systems against their closed forms, rank × thread
# independence with sin/cos, two processes building one kernel at once, NaN lanes, no compiler.
#   test_custom_k.sh CONTACTSWEEP MPIEXEC COMPARE_OUTPUTS.PY
# Last line: "N passed, M failed".
set -uo pipefail
bin=$(realpath "$1") mpiexec=$2 compare=$(realpath "$3")
sweeps=$(cd "$(dirname "$0")/../sweeps" && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export CONTACTSWEEP_CACHE=$work/cache  # every kernel is built afresh by this test
cd "$work"

passed=0 failed=0
ok() { echo "ok    $1"; passed=$((passed + 1)); }
bad() { echo "FAIL  $1"; sed 's/^/      /' "$work/stderr" 2>/dev/null | head -8; failed=$((failed + 1)); }
# check NAME COMMAND...: passes when COMMAND succeeds.
check() { local name=$1; shift; if "$@" 2>"$work/stderr"; then ok "$name"; else bad "$name"; fi; }
run() { "$bin" run "$@" --quiet; }
# The kernel libraries in the cache, one line each: inode, mtime (ns) and path. Wherever the
# cache puts them under CONTACTSWEEP_CACHE, they are named kernel-<key>.so.
libraries() { find "$CONTACTSWEEP_CACHE" -name 'kernel-*.so' -printf '%i %T@ %p\n' 2>/dev/null | sort; }

py() { /usr/bin/python3 -c "$1"; }

# ---- the paper's scenes written as K give the built-ins' results, bit for bit -----------------
# The generated scene keeps K's operations in the order written, and its partials come from the
# same dual numbers as the built-ins': K written in a built-in's order gives its exact bits.
# (Another order rounds differently: ~1e-14 relative after 1e4 steps on scene D.)
# same_data A B: every dataset of A equals B's bit for bit (NaN included); only root attributes
# that say which scene ran (scene, K, spec, title, history, hamiltonian) may differ. A ran the
# built-in and B a K: a K variant made by sed from a file whose line stopped matching would be
# the built-in again, and compare it with itself.
same_data() {
  py "
import h5py, numpy as np
a, b = h5py.File('$1'), h5py.File('$2')
assert a.attrs['scene'] != 'custom', ('$1 ran a custom scene', a.attrs['scene'])
assert b.attrs['scene'] == 'custom' and b.attrs['K'], ('$2 did not run its K', b.attrs['scene'])
assert set(a) == set(b), (sorted(a), sorted(b))
for v in a:
    x, y = a[v][...], b[v][...]
    assert x.dtype == y.dtype and x.shape == y.shape, v
    if x.dtype.kind == 'f':
        x, y = x.view(np.uint64), y.view(np.uint64)
    assert np.array_equal(x, y), v
"
}
cat >builtin.toml <<'EOF'
[scene]
name = "double_well"
[initial]
z = 1.0    # the built-in's default; a custom scene's variables start at 0
[integrator]
method = "METHOD"
h = 0.01
t_end = 10.0
[grid]
q_0 = { from = -2.0, to = 2.0, n = 16 }
p_0 = { from = -1.0, to = 1.0, n = 4 }
[measures]
final_state = true
EOF
sed 's|^name = "double_well"|K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"\na = 1.0\ngamma = 0.1|' builtin.toml >as_k.toml
for method in hybrid_leapfrog symmetric_leapfrog contact_splitting4 contact_splitting6 rk4; do
  sed -i "s/^method = .*/method = \"$method\"/" builtin.toml as_k.toml
  if run builtin.toml -o "b_$method.h5" 2>"$work/stderr" && run as_k.toml -o "k_$method.h5" 2>"$work/stderr"; then
    check "double well as K equals the built-in bit for bit ($method)" same_data "b_$method.h5" "k_$method.h5"
  else bad "double well as K runs ($method)"; fi
done
# One step kernel holds every fixed-step method of its K (engine/step_kernel.hpp): the first
# method's run built it, and the four after it compiled nothing.
check "five methods of one K built one kernel ($(libraries | wc -l))" test "$(libraries | wc -l)" = 1
check "a custom scene's output names its K and label" py "
import h5py
f = h5py.File('k_rk4.h5')
assert f.attrs['K'] == 'p^2/2 + (q^2 - a^2)^2/2 - gamma*z' and f.attrs['scene'] == 'custom'
"
# A run that asks for z or ln lambda alone carries that one (Carry{z, mu}: a step kernel per
# pairing); K_z is constant and z does not feed back, so each is the built-in's bits only if the
# kernel carries what was asked (z or ln lambda swapped went unseen by the runs above, which
# carry both).
for vars in '"q", "z"' '"p", "lambda"'; do
  tag=$(echo "$vars" | tr -dc 'a-z_')
  for spec in builtin as_k; do
    sed -e "s|^final_state = true|final_state = { vars = [$vars] }|" \
        -e 's/^method = .*/method = "rk4"/' $spec.toml >"${spec}_$tag.toml"
  done
  if run "builtin_$tag.toml" -o "b_$tag.h5" 2>"$work/stderr" && run "as_k_$tag.toml" -o "k_$tag.h5" 2>"$work/stderr"; then
    check "K carrying only [$vars] equals the built-in bit for bit" same_data "b_$tag.h5" "k_$tag.h5"
  else bad "K carrying only [$vars] runs"; fi
done
# The paper's figure specs (trajectories; D over a grid of g) with `name` replaced by K.
paper_as_k() {  # paper_as_k FIGURE NAME K [EXTRA-SCENE-LINE]
  sed "s|^name = \"$2\"|K = \"$3\"${4:+\\n$4}|" "$sweeps/paper_$1.toml" >"k_$1.toml"
  if run "$sweeps/paper_$1.toml" -o "b_$1.h5" 2>"$work/stderr" && run "k_$1.toml" -o "k_$1.h5" 2>"$work/stderr"; then
    check "paper $1 ($2) as K equals the built-in bit for bit" same_data "b_$1.h5" "k_$1.h5"
  else bad "paper $1 as K runs"; fi
}
paper_as_k fig1a damped_oscillator "p^2/2 + omega^2*q^2/2 - gamma*z"
paper_as_k fig1b z2_damping "p^2/2 + omega^2*q^2/2 - gamma*z^2"
paper_as_k fig3 coupled_oscillators \
  "p1^2/2 + p2^2/2 + 0.5*(omega1_sq*q1^2) + 0.5*(omega2_sq*q2^2) + g*(q1^2*q2^2) - gamma*z" \
  "g = 0.0  # swept by the grid"

# Synchronization of any two degrees of freedom: scene D's sync map written as K, with the
# frequencies that scale p given in the spec (the built-in takes them from its parameters),
# gives the same phases, frequencies and locking bit for bit.
omegas=$(/usr/bin/python3 -c 'import math; print(f"omega = [{math.sqrt(1.2)!r}, {math.sqrt(0.8)!r}], ")')
sed -e 's|^name = "coupled_oscillators"|K = "p1^2/2 + p2^2/2 + 0.5*(omega1_sq*q1^2) + 0.5*(omega2_sq*q2^2) + g*(q1^2*q2^2) - gamma*z"\ng = 0.0\ngamma = 0.0|' \
    -e "s|^sync = { window|sync = { ${omegas}dof = [1, 2], window|" \
    -e 's|n = 128|n = 16|; s|n = 64|n = 8|' "$sweeps/sync_g_gamma.toml" >k_sync.toml
sed -e 's|n = 128|n = 16|; s|n = 64|n = 8|' "$sweeps/sync_g_gamma.toml" >b_sync.toml
if run b_sync.toml -o b_sync.h5 2>"$work/stderr" && run k_sync.toml -o k_sync.h5 2>"$work/stderr"; then
  check "sync of scene D written as K equals the built-in bit for bit" same_data b_sync.h5 k_sync.h5
else bad "sync on K runs: $(cat "$work/stderr")"; fi

# ---- which kernel a run builds: a step kernel where the program's runner does the rest --------
# Every run above (no basin map, a fixed-step method) ran K through the program's own block
# runner and a step kernel (engine/step_kernel.hpp: the step loop and the scene's per-lane
# functions): the bit-for-bit comparisons above are the step kernel's against the built-ins.
step_sources() { grep -l contactsweep_step_kernel $(find "$CONTACTSWEEP_CACHE" -name 'kernel-*.cpp') | wc -l; }
whole_sources() { grep -L contactsweep_step_kernel $(find "$CONTACTSWEEP_CACHE" -name 'kernel-*.cpp') | wc -l; }
check "runs without a basin map built step kernels only ($(step_sources) of them)" \
  test "$(whole_sources)" = 0 -a "$(step_sources)" -ge 5
# Basin maps run on a step kernel too, with the mappers in the program; a map that uses the
# energy trap builds the kernel with the trap's uses of K (its screen's E over a tile, the
# wells, a well's bottom: engine/step_kernel.hpp's StepKernelTrap). The double well's map as K
# equals the built-in's bit for bit in every dataset, the attractors' description too (their
# fixed points' λ₁ from K's exact Jacobian, one formula for both), but its labels' names (the
# built-in names its wells by the sign of q, a K numbers them): `basin` is the same partition,
# 0 (undecided) kept. same_map BUILTIN K VERDICT (the energy_trap attribute)
# CLASSES (how many the partition has: with t_end = 10, only the trap settles lanes)
same_map() {
  py "
import h5py, numpy as np
a, b = h5py.File('$1'), h5py.File('$2')
assert a.attrs['energy_trap'] == b.attrs['energy_trap'] == '$3', (a.attrs['energy_trap'], b.attrs['energy_trap'])
assert set(a) == set(b), (sorted(a), sorted(b))
compared = 0
for v in a:
    if v in ('attractor', 'attractor_label') or v.startswith('branch_'):
        continue
    x, y = a[v][...], b[v][...]
    assert x.dtype == y.dtype and x.shape == y.shape, v
    if v == 'basin':
        pairs = set(zip(x.ravel().tolist(), y.ravel().tolist()))
        assert len(pairs) == len({u for u, _ in pairs}) == len({w for _, w in pairs}) == $4, pairs
        assert (0, 0) in pairs, pairs
    else:
        if x.dtype.kind == 'f':
            x, y = x.view(np.uint64), y.view(np.uint64)
        assert np.array_equal(x, y), v
    compared += 1
assert 'basin' in a and 'attractor_lyapunov' in a and compared >= 8, sorted(a)
"
}
# A step kernel's source with the trap's entries: its step_kernel_of's fourth argument
# (kernel_build/kernel_source.cpp), the line before the measures' struct.
trap_sources() {
  grep -lE '^ +true, cs::[A-Za-z0-9]+>\(method\)' $(find "$CONTACTSWEEP_CACHE" -name 'kernel-*.cpp') | wc -l
}
for with_trap in 0 1; do
  options=("exact_trap = false" "")
  verdicts=("not used: measures.basin.exact_trap = false" "used")
  verdict=${verdicts[with_trap]}
  sed -e "s|^final_state = true|basin = { ${options[with_trap]} }|" builtin.toml >b_map.toml
  sed -e "s|^final_state = true|basin = { ${options[with_trap]} }|" as_k.toml >k_map.toml
  sed -i 's/^method = .*/method = "rk4"/' b_map.toml k_map.toml
  steps_before=$(step_sources) traps_before=$(trap_sources)
  if run b_map.toml -o "b_map$with_trap.h5" 2>"$work/stderr" &&
     run k_map.toml -o "k_map$with_trap.h5" 2>"$work/stderr"; then
    check "a basin map (energy trap: $verdict), K on a step kernel, equals the built-in bit for bit" \
      same_map "b_map$with_trap.h5" "k_map$with_trap.h5" "$verdict" $((1 + 2 * with_trap))
    check "the basin map (energy trap: $verdict) built a step kernel, $with_trap with the trap's entries" \
      test "$(step_sources)" = $((steps_before + 1)) -a "$(trap_sources)" = $((traps_before + with_trap))
  else bad "basin map (energy trap: $verdict) runs"; fi
done
# A map that does not span the wells but the saddle (|q0| <= 0.3, |p0| <= 2): the trap's box
# grows until V on its boundary is above the lanes' largest E0 (confining_box, E0 from the
# program through the step kernel's table), and holds both wells; the same step kernel as the
# map above (no compile). With E0 and h swapped on the way to the kernel the box stayed small
# and the trap settled none of the 82 lanes the built-in's settles by t = 10.
for spec in builtin as_k; do
  sed -e "s|^final_state = true|basin = {}|" -e 's/^method = .*/method = "rk4"/' \
      -e 's|^q_0 = .*|q_0 = { from = -0.3, to = 0.3, n = 16 }|' \
      -e 's|^p_0 = .*|p_0 = { from = -2.0, to = 2.0, n = 8 }|' $spec.toml >"${spec}_saddle.toml"
done
if run builtin_saddle.toml -o b_map_saddle.h5 2>"$work/stderr" && run as_k_saddle.toml -o k_map_saddle.h5 2>"$work/stderr"; then
  check "a basin map around the saddle (the trap's box grown to hold E0), K on a step kernel, equals the built-in bit for bit" \
    same_map b_map_saddle.h5 k_map_saddle.h5 used 3
else bad "basin map around the saddle runs"; fi
# The same over a parameter axis (a first: continuation keeps two labels): each lane its own
# wells, and the trap's screen takes each lane's E from its own parameters (the step kernel's
# tile_energy with per-lane fields; with lane 0's parameters for every lane it went unseen, the
# settle times later, the labels kept). branch_q/branch_p are the attractors' description too.
for spec in builtin as_k; do
  sed -e "s|^final_state = true|basin = {}|" -e 's/^method = .*/method = "rk4"/' \
      -e 's|^\[grid\]|[grid]\na = { values = [0.9, 1.1] }|' $spec.toml >"${spec}_over_a.toml"
done
steps_before=$(step_sources) traps_before=$(trap_sources)
if run builtin_over_a.toml -o b_map_a.h5 2>"$work/stderr" && run as_k_over_a.toml -o k_map_a.h5 2>"$work/stderr"; then
  check "a basin map over a (energy trap: used, per-lane parameters), K on a step kernel, equals the built-in bit for bit" \
    same_map b_map_a.h5 k_map_a.h5 used 3
  check "the basin map over a built a step kernel with the trap's entries" \
    test "$(step_sources)" = $((steps_before + 1)) -a "$(trap_sources)" = $((traps_before + 1))
else bad "basin map over a runs"; fi
# A K of more degrees of freedom than the program's runners (kStepKernelMaxDof = 3) builds a
# whole kernel, and agrees with the step kernel of its one-dof part: with K_z constant and no z in
# the forces, each (q_i, p_i) takes the same operations as a one-dof K's, bit for bit.
cat >one.toml <<'EOF'
[scene]
K = "p^2/2 + q^2/2 + q^4/4 - gamma*z"
gamma = 0.1
[initial]
p = 0.3
[integrator]
method = "symmetric_leapfrog"
h = 0.01
t_end = 10.0
[grid]
q_0 = { from = -1.5, to = 1.5, n = 4 }
[measures]
final_state = { vars = ["q", "p"] }
EOF
cat >four.toml <<'EOF'
[scene]
K = "p1^2/2 + q1^2/2 + q1^4/4 + p2^2/2 + q2^2/2 + q2^4/4 + p3^2/2 + q3^2/2 + q3^4/4 + p4^2/2 + q4^2/2 + q4^4/4 - gamma*z"
gamma = 0.1
[initial]
q1 = -1.5
q2 = -0.5
q3 = 0.5
q4 = 1.5
p1 = 0.3
p2 = 0.3
p3 = 0.3
p4 = 0.3
[integrator]
method = "symmetric_leapfrog"
h = 0.01
t_end = 10.0
[measures]
final_state = { vars = ["q1", "q2", "q3", "q4", "p1", "p2", "p3", "p4"] }
EOF
steps_before=$(step_sources) whole_before=$(whole_sources)
if run one.toml -o one.h5 2>"$work/stderr" && run four.toml -o four.h5 2>"$work/stderr"; then
  check "a four-dof K (a whole kernel) equals its one-dof parts (a step kernel) bit for bit" py "
import h5py, numpy as np
one, four = h5py.File('one.h5'), h5py.File('four.h5')
for v in 'qp':
    a = one['final_' + v][...]
    b = np.array([four['final_%s%d' % (v, i)][...].item() for i in range(1, 5)])
    assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), (v, a, b)
"
  check "the one-dof K built a step kernel, the four-dof K a whole one" \
    test "$(step_sources)" = $((steps_before + 1)) -a "$(whole_sources)" = $((whole_before + 1))
else bad "one- and four-dof K run"; fi

# ---- time-dependent K against closed forms --------------------------------------------------
# Forced damped oscillator, RK4 at h = 0.01 from t_start = 0.5 to 10.5: error ~ h⁴ ≈ 1e-8·C;
# a time off by t_start would be O(F) = O(0.1).
cat >forced.toml <<'EOF'
[scene]
K = "p^2/2 + w^2*q^2/2 - F*q*cos(W*t) - gamma*z"
w = 1.0
gamma = 0.1
F = 0.5
W = 1.3
[initial]
q = 1.0
[integrator]
method = "rk4"
t_start = 0.5
h = 0.01
t_end = 10.5
[measures]
final_state = true
trajectory = { every = 100 }
EOF
if run forced.toml -o forced.h5 2>"$work/stderr"; then
  check "forced oscillator: closed form at t_end, true sample times, exact ln lambda" py "
import h5py, numpy as np
f = h5py.File('forced.h5')
w, g, F, W, t0, t = 1.0, 0.1, 0.5, 1.3, 0.5, 10.5
D = (w*w - W*W)**2 + g*g*W*W; A = F*(w*w - W*W)/D; B = F*g*W/D
qp = lambda s: A*np.cos(W*s) + B*np.sin(W*s)
pp = lambda s: W*(B*np.cos(W*s) - A*np.sin(W*s))
q0, p0 = 1.0 - qp(t0), 0.0 - pp(t0); O = np.sqrt(w*w - g*g/4); s = t - t0
qh = np.exp(-g*s/2)*(q0*np.cos(O*s) + (p0 + g*q0/2)/O*np.sin(O*s))
ph = np.exp(-g*s/2)*(p0*np.cos(O*s) - (w*w*q0 + g*p0/2)/O*np.sin(O*s))
assert abs(f['final_q'][()] - (qh + qp(t))) < 1e-7, f['final_q'][()] - (qh + qp(t))
assert abs(f['final_p'][()] - (ph + pp(t))) < 1e-7
assert abs(f['final_log_lambda'][()] - g*(t - t0)) < 1e-12
assert np.allclose(f['t'][...], 0.5 + np.arange(11), rtol=0, atol=1e-12), f['t'][...]
assert f.attrs['t_start'] == 0.5
"
else bad "forced oscillator runs"; fi

# Lane–Emden n = 5 from t = 1 with the hybrid leap-frog (h = 0.01): second order, error ≲ 1e-4·C;
# its λ factors give ln λ = 2 ln(t/t0) exactly (tests/test_methods.cpp).
cp "$sweeps/lane_emden.toml" lane_emden.toml
if run lane_emden.toml -o lane.h5 2>"$work/stderr"; then
  check "Lane-Emden n = 5: exact solution and exact ln lambda" py "
import h5py, numpy as np
f = h5py.File('lane.h5')
t = f['t'][...]
q = f['traj_q'][...]
assert np.max(np.abs(q - (1 + t*t/3)**-0.5)) < 1e-4, np.max(np.abs(q - (1 + t*t/3)**-0.5))
assert abs(f['final_log_lambda'][()] - 2*np.log(21.0)) < 1e-12
"
else bad "Lane-Emden runs"; fi
# n = 1 (the spec's comment shows how): θ = sin(t)/t; measured error 3.7e-6 at h = 0.01.
if run lane_emden.toml -o lane1.h5 --set 'scene.K="p^2/2 + q^2/2 - (2/t)*z"' \
     --set initial.q=0.8414709848078965 --set initial.p=-0.30116867893975674 2>"$work/stderr"; then
  check "Lane-Emden n = 1: exact solution sin(t)/t" py "
import h5py, numpy as np
f = h5py.File('lane1.h5')
t, q = f['t'][...], f['traj_q'][...]
assert np.max(np.abs(q - np.sin(t)/t)) < 1e-4, np.max(np.abs(q - np.sin(t)/t))
"
else bad "Lane-Emden n = 1 runs"; fi

# ---- same bits for any ranks × threads, with sin and cos in K --------------------------------
cat >duffing.toml <<'EOF'
[scene]
K = "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z + 0.01*sin(q)*exp(-t/50)"
delta = 0.25
F = 0.3
Omega = 1.2
[integrator]
method = "symmetric_leapfrog"
h = 0.02
t_end = 20.0
[grid]
q_0 = { from = -2.0, to = 2.0, n = 37 }
F = { values = [0.1, 0.3] }
[measures]
final_state = true
EOF
run duffing.toml -o d11.h5 2>"$work/stderr" || bad "duffing 1x1 runs"
OMP_NUM_THREADS=2 run duffing.toml -o d12.h5 2>"$work/stderr" || bad "duffing 1x2 runs"
$mpiexec -np 2 --oversubscribe "$bin" run duffing.toml -o d21.h5 --quiet 2>"$work/stderr" || bad "duffing 2x1 runs"
$mpiexec -np 3 --oversubscribe "$bin" run duffing.toml -o d31.h5 --quiet 2>"$work/stderr" || bad "duffing 3x1 runs"
for o in d12 d21 d31; do
  check "time-dependent K: $o equals 1x1 bit for bit" /usr/bin/python3 "$compare" d11.h5 "$o.h5"
done
# A swept parameter of K needs no value under [scene]: without `F = 0.3` the same data, bit for
# bit (only the stored spec text differs), from the same cached kernel.
sed '/^F = 0.3$/d' duffing.toml >duffing_swept.toml
run duffing_swept.toml -o dsw.h5 2>"$work/stderr" || bad "duffing without a value for the swept F runs"
check "swept parameter of K without a value under [scene]: the same datasets" py "
import h5py, numpy as np
a, b = h5py.File('d11.h5', 'r'), h5py.File('dsw.h5', 'r')
names = sorted(k for k in a if isinstance(a[k], h5py.Dataset))
assert names == sorted(b) and 'final_q' in names, (names, sorted(b))
for k in names:
    assert np.array_equal(a[k][()].view(np.uint8), b[k][()].view(np.uint8)), k
assert 'F = 0.3' in a.attrs['spec'] and 'F = 0.3' not in b.attrs['spec']
"

# ---- two processes building the same new K at once build it once -----------------------------
export CONTACTSWEEP_CACHE=$work/cache2
sed 's/- delta\*z/- delta*z + 0.001*q^3/' duffing.toml >race.toml
"$bin" run race.toml -o race1.h5 2>race1.err & pid1=$!
"$bin" run race.toml -o race2.h5 2>race2.err & pid2=$!
wait $pid1; rc1=$?; wait $pid2; rc2=$?
built=$(cat race1.err race2.err | grep -c "built the kernel")
if ((rc1 == 0 && rc2 == 0 && built == 1)) && [[ $(libraries | wc -l) == 1 ]] &&
   /usr/bin/python3 "$compare" race1.h5 race2.h5 2>"$work/stderr"; then
  ok "two processes building one K at once: one build, both run, same bits"
else
  echo "rc $rc1 $rc2, builds $built, libraries: $(libraries)" >"$work/stderr"
  cat race1.err race2.err >>"$work/stderr"
  bad "two processes building one K at once"
fi
# A cached kernel is loaded, not rebuilt: the library keeps its inode and mtime, no other library
# appears, and the run does not say it built one (without --quiet, which would hide that line).
before=$(libraries)
"$bin" run race.toml -o race3.h5 2>"$work/stderr"
rc=$?
if ((rc == 0)) && [[ -n $before && $(libraries) == "$before" ]] && ! grep -q "built the kernel" "$work/stderr"; then
  ok "a cached kernel is loaded, not rebuilt"
else
  echo "exit $rc; libraries before: ${before:-none}; after: $(libraries)" >>"$work/stderr"
  bad "a cached kernel is loaded, not rebuilt"
fi
# ...and a kernel missing from the cache is built: a new library appears (another inode or
# mtime than the one removed), and the run says so.
find "$CONTACTSWEEP_CACHE" -name 'kernel-*.so' -delete
"$bin" run race.toml -o race4.h5 2>"$work/stderr"
rc=$?
if ((rc == 0)) && [[ $(libraries | wc -l) == 1 && $(libraries) != "$before" ]] &&
   grep -q "built the kernel" "$work/stderr"; then
  ok "a kernel missing from the cache is built again"
else
  echo "exit $rc; libraries after: $(libraries)" >>"$work/stderr"
  bad "a kernel missing from the cache is built again"
fi

# ---- lanes where K is NaN are flagged, the run succeeds ----------------------------------------
cat >nan.toml <<'EOF'
[scene]
K = "p^2/2 + q*log(q) - gamma*z"
gamma = 0.1
[initial]
q = 1.0
[integrator]
h = 0.01
t_end = 1.0
[grid]
q_0 = { from = -1.0, to = 2.0, n = 13 }
[measures]
final_state = true
EOF
if run nan.toml -o nan.h5 2>"$work/stderr"; then
  # K = q log q is NaN at q0 < 0 and at q0 = 0 (0 * -inf): status 4, K undefined at the initial
  # state (it was 1, diverged, before that flag existed).
  check "lanes where K is NaN at the start are flagged 4 (K undefined), the others ok" py "
import h5py, numpy as np
f = h5py.File('nan.h5')
q0, s = f['q_0'][...], f['status'][...]
assert (s[q0 <= 0] == 4).all(), s
assert (s[q0 > 0.2] == 0).all(), s
"
else bad "a K that is NaN on some lanes runs"; fi

# ---- no compiler: a clear error, exit 1, nothing written ---------------------------------------
export CONTACTSWEEP_CACHE=$work/cache3
mkdir -p nocc
rc=0
(cd nocc && CONTACTSWEEP_CXX=/nonexistent/g++ "$bin" run ../race.toml -o out.h5) 2>"$work/stderr" || rc=$?
if ((rc == 1)) && grep -q "cannot run the C++ compiler" "$work/stderr" && [[ -z $(ls -A nocc) ]]; then
  ok "no compiler: exit 1, a clear message, nothing written"
else bad "no compiler (exit $rc)"; fi

echo "$passed passed, $failed failed"
((failed == 0))
