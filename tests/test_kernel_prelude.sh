#!/usr/bin/env bash
# A kernel of K compiles against its precompiled prelude (kernel_build/kernel_prelude.hpp.gch for
# a whole kernel, step_kernel_prelude.hpp.gch for a step kernel): the compiler, wrapped to print
# its include tree (-H), must mark the .gch as used ("! path"),
# not as tried and rejected ("x path": flags, macros or compiler differ from the build's), and
# must not read the prelude's text instead. A drift between the build's precompile command
# (src/CMakeLists.txt) and the kernels' own (kernel_cache.cpp) fails here, not silently slow.
#   test_kernel_prelude.sh CONTACTSWEEP CXX
set -uo pipefail
bin=$(realpath "$1") cxx=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cat >cxx <<WRAP
#!/bin/sh
exec "$cxx" -H "\$@" 2>>"$work/tree.txt"
WRAP
chmod 700 cxx
cat >k.toml <<'SPEC'
[scene]
K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"
a = 1.0
gamma = 0.1
[integrator]
method = "dop853"  # a whole kernel (a fixed-step method's map would build a step kernel)
rtol = 1e-8
h = 0.01
t_end = 0.1
[grid]
q_0 = { from = -1.0, to = 1.0, n = 4 }
p_0 = { from = -1.0, to = 1.0, n = 2 }
[measures]
final_state = true
# the recurrences (a lane's cell set): a kernel holds only the mappers its run uses
basin = { recurrence = true }
SPEC
CONTACTSWEEP_CXX=$work/cxx CONTACTSWEEP_CACHE=$work/cache OMP_NUM_THREADS=1 \
  "$bin" run k.toml -o k.h5 --quiet 2>stderr
rc=$?
fail=0
check() { if eval "$2"; then echo "ok    $1"; else echo "FAIL  $1"; fail=1; fi; }
check "the run exits 0 (exit $rc; $(head -c 300 stderr))" '[[ $rc == 0 ]]'
check "the compiler used the precompiled prelude: $(grep -m1 'kernel_prelude' tree.txt)" \
  'grep -q "^! .*/kernel_build/kernel_prelude\.hpp\.gch$" tree.txt'
check "no precompiled header was rejected" '! grep -q "^x " tree.txt'
check "the prelude's text was not read (the .gch stands for it)" \
  '! grep -q "^\. .*/kernel_build/kernel_prelude\.hpp$" tree.txt'
# A run without a basin map builds a step kernel (engine/step_kernel.hpp), against the smaller
# prelude of the step loop alone.
sed -e 's/^basin = .*/# none/' -e 's/^method = .*/method = "rk4"/' -e '/^rtol/d' k.toml >step.toml
: >tree.txt
CONTACTSWEEP_CXX=$work/cxx CONTACTSWEEP_CACHE=$work/cache OMP_NUM_THREADS=1 \
  "$bin" run step.toml -o step.h5 --quiet 2>stderr
rc=$?
check "the step kernel's run exits 0 (exit $rc; $(head -c 300 stderr))" '[[ $rc == 0 ]]'
check "the step kernel used its precompiled prelude: $(grep -m1 'step_kernel_prelude' tree.txt)" \
  'grep -q "^! .*/kernel_build/step_kernel_prelude\.hpp\.gch$" tree.txt'
check "no precompiled header was rejected" '! grep -q "^x " tree.txt'
check "the step kernel read no header's text (the .gch holds all it includes): $(grep -m1 '^\.' tree.txt)" \
  '! grep -q "^\.\+ " tree.txt'
# The engine's code that does not depend on the scene is the program's, compiled once
# (engine/engine_export.hpp): the kernel calls it there, and the program exports that and no
# more of the engine.
kernel=""  # the runner's (a basin map may add the attractors' orbit kernel)
for k in cache/kernel-*.so; do  # to a file, not a pipe: grep -q under pipefail
  nm -D --defined-only "$k" >entries.txt 2>/dev/null
  grep -q " contactsweep_run_block$" entries.txt && kernel=$k
done
[[ -n $kernel ]] && nm -D --undefined-only "$kernel" >kernel_needs.txt
nm -D --defined-only "$bin" >program_exports.txt  # files, not pipes: grep -q under pipefail
check "the kernel calls the program's CellSet::visit, not a copy of its own ($kernel)" \
  'grep -q " _ZN2cs7CellSet5visitEmb$" kernel_needs.txt'
check "the program exports CellSet::visit" 'grep -q " _ZN2cs7CellSet5visitEmb$" program_exports.txt'
extra=$(c++filt <program_exports.txt | grep " cs::" |
        grep -v " cs::CellSet::\| cs::CellGrid<\| cs::SettlementRecords<" | head -3)
check "the program exports nothing else of the engine (${extra:-none})" '[[ -z $extra ]]'
exit $fail
