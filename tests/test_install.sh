#!/usr/bin/env bash
# An installed contactsweep builds a K kernel from its installed headers alone: install into a
# fresh prefix and run a custom K from there (the installed headers come first, kernel_cache.cpp),
# and its output has the bits of the build tree's program.
#   test_install.sh CMAKE BUILD_DIR CONTACTSWEEP COMPARE_OUTPUTS.PY
# Last line: "N passed, M failed"; exit status 1 if any failed.
set -uo pipefail
cmake=$1 build=$2 built_bin=$(realpath "$3") compare=$(realpath "$4")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export CONTACTSWEEP_CACHE=$work/cache
passed=0 failed=0
ok() { echo "ok    $1"; passed=$((passed + 1)); }
bad() { echo "FAIL  $1"; sed 's/^/      /' "$work/log" | tail -8; failed=$((failed + 1)); }

if "$cmake" --install "$build" --prefix "$work/prefix" >"$work/log" 2>&1; then
  ok "cmake --install into a fresh prefix"
else bad "cmake --install into a fresh prefix"; fi
cat >"$work/spec.toml" <<'SPEC'
[scene]
K = "p^2/2 + q^2/2 - F*q*cos(t) - gamma*z"
F = 0.1
gamma = 0.2
[initial]
q = 1.0
[integrator]
h = 0.01
t_end = 1.0
[measures]
final_state = true
SPEC
if (cd "$work" && "$work/prefix/bin/contactsweep" run spec.toml -o out.h5) >"$work/log" 2>&1 &&
   grep -q "built the kernel of scene.K" "$work/log" && [[ -s $work/out.h5 ]]; then
  ok "the installed program builds and runs a K kernel"
else bad "the installed program builds and runs a K kernel"; fi
# The same spec with the build tree's program (a cache of its own, so it builds its own kernel).
if (cd "$work" && CONTACTSWEEP_CACHE=$work/build_cache "$built_bin" run spec.toml -o build_tree.h5 --quiet) \
     >"$work/log" 2>&1 && /usr/bin/python3 "$compare" "$work/build_tree.h5" "$work/out.h5" >>"$work/log" 2>&1; then
  ok "the installed program's output equals the build tree's, bit for bit"
else bad "the installed program's output equals the build tree's, bit for bit"; fi
# The generated source compiles against the installed headers alone (no source tree on -I).
mpi_dirs=()
for d in $(mpicxx --showme:incdirs 2>/dev/null); do mpi_dirs+=("-isystem" "$d"); done
source=$(find "$work/cache" -name 'kernel-*.cpp' 2>/dev/null | head -1)
if [[ -n $source ]] && c++ -std=c++20 -fsyntax-only -I"$work/prefix/share/contactsweep/include" \
     "${mpi_dirs[@]}" "$source" >"$work/log" 2>&1; then
  ok "the kernel source needs only the installed headers"
else bad "the kernel source needs only the installed headers"; fi
# The Python module, when the build has it: the installed package is the one imported, finds
# the installed headers for its K kernel, and returns the installed program's values.
if [[ -f $build/python/contactsweep/__init__.py ]]; then
  site=("$work"/prefix/lib/python3*/dist-packages)
  if (cd "$work" && PYTHONPATH=${site[0]} /usr/bin/python3 -c '
import sys, h5py, contactsweep
assert contactsweep.__file__.startswith(sys.argv[1]), contactsweep.__file__
ds = contactsweep.run("spec.toml", progress=False)
with h5py.File("out.h5") as f:
    assert ds.final_q.values.tobytes() == f["final_q"][()].tobytes()
' "${site[0]}") >"$work/log" 2>&1; then
    ok "the installed Python module runs a K kernel with the installed program's bits"
  else bad "the installed Python module runs a K kernel with the installed program's bits"; fi
fi
echo "$passed passed, $failed failed"
((failed == 0))
