#!/usr/bin/env bash
# Trust on a shared machine (issue 22): what another user plants beside an output or in a kernel
# cache is never followed, cleared, compiled in or loaded. As root (CI) the planting is done by a
# second user and the victim is a third, both created here; without root the cases that need
# them are reported as skipped (exit 77), the rest still run.
#   test_security.sh CONTACTSWEEP COMPARE_OUTPUTS.PY
# Last line: "N passed, M failed, K skipped"; exit 1 when any failed.
set -uo pipefail
bin=$(realpath "$1") compare=$(realpath "$2")
source_dir=$(realpath "$(dirname "${BASH_SOURCE[0]}")/..")  # examples/ and jobs/ are run from here
export OMP_NUM_THREADS=1
work=$(mktemp -d)
chmod 755 "$work"  # the test users must reach their directories inside
trap 'rm -rf "$work"' EXIT
cd "$work"

passed=0 failed=0 skipped=0
ok() { echo "ok    $1"; passed=$((passed + 1)); }
bad() { echo "FAIL  $1${2:+: $2}"; sed 's/^/      /' "$work/stderr" 2>/dev/null | head -8; failed=$((failed + 1)); }
skip() { echo "skip  $1 ($2)"; skipped=$((skipped + 1)); }
same() { /usr/bin/python3 "$compare" "$1" "$2" >/dev/null 2>&1; }

cat >k.toml <<'EOF'
[scene]
K = "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"
a = 1.0
gamma = 0.1
[integrator]
h = 0.01
t_end = 2.0
[grid]
q_0 = { from = -2.0, to = 2.0, n = 8 }
p_0 = { from = -1.0, to = 1.0, n = 3 }
[measures]
final_state = true
EOF
sed 's|^K = .*|K = "p^2/2 + (q^2 - a^2)^2/4 - gamma*z"|' k.toml >k_other.toml

# The reference: a private cache, nothing planted anywhere.
export CONTACTSWEEP_CACHE=$work/cache
"$bin" run k.toml -o ref.h5 --quiet 2>stderr || { bad "reference run"; exit 1; }
lib=$(ls cache/kernel-*.so)  # k.toml's, the only one so far
"$bin" run k_other.toml -o ref_other.h5 --quiet 2>stderr || { bad "reference run (other K)"; exit 1; }
[[ $(stat -c %a cache) == 700 ]] && ok "the cache is created 0700" || bad "the cache is created 0700" "mode $(stat -c %a cache)"

# ---- 1. the journal is never followed, nor cleared beyond its own names -------------------------
make_precious() {
  rm -rf precious && mkdir -p precious/sub && echo keep >precious/file && echo keep >precious/sub/file
  echo keep >precious/block_0.bin
}
precious_intact() {
  [[ -f precious/file && -f precious/sub/file && -f precious/block_0.bin ]]
}
for flags in "" "--force" "--resume"; do
  make_precious
  rm -rf out && mkdir out && ln -s ../precious out/map.h5.journal
  "$bin" run k.toml -o out/map.h5 $flags --quiet 2>stderr
  rc=$?
  if ((rc == 2)) && precious_intact && grep -q "symbolic link" stderr && [[ ! -e out/map.h5 ]]; then
    ok "a journal that is a link is refused (exit 2, ${flags:-no flag}), its target untouched"
  else
    bad "a journal that is a link is refused (${flags:-no flag})" "exit $rc"
  fi
done

rm -rf out && mkdir out && mkdir -m 0777 out/map.h5.journal && echo keep >out/map.h5.journal/notes
chmod 0777 out/map.h5.journal  # whatever the umask
"$bin" run k.toml -o out/map.h5 --force --quiet 2>stderr
rc=$?
((rc == 2)) && [[ -f out/map.h5.journal/notes ]] && grep -q "others can write to it" stderr &&
  ok "a journal others can write to is refused (exit 2), nothing in it removed" ||
  bad "a journal others can write to is refused" "exit $rc"

# Our own journal holding a file it did not make: the run finishes, the file stays, with a word.
rm -rf out && mkdir out && mkdir -m 0700 out/map.h5.journal && mkdir out/map.h5.journal/mine &&
  echo keep >out/map.h5.journal/notes.txt && echo keep >out/map.h5.journal/mine/file
"$bin" run k.toml -o out/map.h5 --quiet 2>stderr
rc=$?
((rc == 0)) && same ref.h5 out/map.h5 && [[ -f out/map.h5.journal/notes.txt && -f out/map.h5.journal/mine/file ]] &&
  [[ -z $(ls out/map.h5.journal | grep -v -e '^notes.txt$' -e '^mine$') ]] && grep -q "did not make" stderr &&
  ok "clearing the journal removes only its own names (a foreign file and directory stay)" ||
  bad "clearing the journal removes only its own names" "exit $rc"

rm -rf out && mkdir out
"$bin" run k.toml -o out/map.h5 --quiet --set integrator.t_end=1.0 2>stderr &&
  [[ ! -e out/map.h5.journal ]] && ok "a finished run leaves no journal" || bad "a finished run leaves no journal"

# The temporary output beside the output: a link planted there is not written through.
make_precious
rm -rf out && mkdir out && ln -s ../precious/file out/map.h5.partial
"$bin" run k.toml -o out/map.h5 --quiet 2>stderr
rc=$?
[[ $(cat precious/file) == keep ]] && ((rc == 0)) && same ref.h5 out/map.h5 && [[ ! -e out/map.h5.partial ]] &&
  ok "a link planted as OUT.h5.partial is removed, never written through" ||
  bad "a link planted as OUT.h5.partial" "exit $rc, precious: $(cat precious/file | head -c 20)"

# ---- 2-5. the kernel cache ----------------------------------------------------------------------
other_lib=$(ls cache/kernel-*.so | grep -v "$lib")

# Another K's kernel under this K's name, then a truncated one: rebuilt, right numbers.
cp "$other_lib" "$lib"
"$bin" run k.toml -o swapped.h5 --quiet 2>stderr
rc=$?
((rc == 0)) && same ref.h5 swapped.h5 && grep -q "built for another kernel" stderr &&
  ok "another K's kernel under this K's name is rebuilt, not loaded (same bits as the reference)" ||
  bad "another K's kernel under this K's name" "exit $rc"
head -c $(($(stat -c %s "$lib") / 2)) "$lib" >truncated && cat truncated >"$lib"  # half of it
"$bin" run k.toml -o truncated.h5 --quiet 2>stderr
rc=$?
((rc == 0)) && same ref.h5 truncated.h5 && grep -q "not fit to load" stderr &&
  ok "a kernel truncated to half its size is rebuilt (no SIGBUS, same bits)" || bad "a truncated kernel" "exit $rc"

# A header planted in the cache (where the source used to be compiled) is not included.
rm -rf cache_h && mkdir -m 0700 cache_h && mkdir -p cache_h/physics cache_h/engine
for h in physics/dual_math.hpp engine/block_runner.hpp; do
  echo '#error "a planted header was compiled in"' >cache_h/$h
done
CONTACTSWEEP_CACHE=$work/cache_h "$bin" run k.toml -o header.h5 --quiet 2>stderr
rc=$?
((rc == 0)) && same ref.h5 header.h5 && ok "headers planted in the cache are not compiled in" ||
  bad "headers planted in the cache" "exit $rc"

# A failed build's log name planted as a link: the build's log never goes through it.
cat >failing_cxx <<EOF
#!/bin/sh
case "\$*" in *--version*) exec g++ --version ;; esac
echo "a compiler that fails" >&2
exit 3
EOF
chmod +x failing_cxx
make_precious
rm -rf cache_f && mkdir -m 0700 cache_f
CONTACTSWEEP_CXX=$work/failing_cxx CONTACTSWEEP_CACHE=$work/cache_f "$bin" run k.toml -o f.h5 --quiet 2>stderr
log=$(ls cache_f/kernel-*.log 2>/dev/null | head -1)
if [[ -n $log ]]; then
  rm -f "$log" && ln -s "$work/precious/file" "$log"
  CONTACTSWEEP_CXX=$work/failing_cxx CONTACTSWEEP_CACHE=$work/cache_f "$bin" run k.toml -o f.h5 --quiet 2>stderr
  rc=$?
  ((rc == 1)) && [[ $(cat precious/file) == keep && -f $log && ! -L $log ]] && grep -q "a compiler that fails" stderr &&
    ok "a link planted as the compiler's log is replaced, its target untouched (exit 1, the compiler's words)" ||
    bad "a link planted as the compiler's log" "exit $rc"
else
  bad "a failed build keeps its log in the cache" "no kernel-*.log"
fi

# The compiler's identity is its --version output, not only its path.
for v in A B; do
  cat >cxx_$v <<EOF
#!/bin/sh
case "\$*" in *--version*) echo "g++ (version $v)"; exit 0 ;; esac
exec g++ "\$@"
EOF
  chmod +x cxx_$v
done
rm -rf cache_v && mkdir -m 0700 cache_v
ln -sf cxx_A cxx
CONTACTSWEEP_CXX=$work/cxx CONTACTSWEEP_CACHE=$work/cache_v "$bin" run k.toml -o va.h5 --quiet 2>stderr
ln -sf cxx_B cxx
CONTACTSWEEP_CXX=$work/cxx CONTACTSWEEP_CACHE=$work/cache_v "$bin" run k.toml -o vb.h5 --quiet 2>>stderr
n=$(ls cache_v/kernel-*.so 2>/dev/null | wc -l)
((n == 2)) && same ref.h5 vb.h5 && ok "a compiler that reports another version builds its own kernel (2 libraries)" ||
  bad "a compiler that reports another version" "$n libraries"

# Headers other than the build's own snapshot are refused: an installed-looking copy of the
# program whose header snapshot was changed afterwards (a newer build's, or an edit).
rm -rf prefix && mkdir -p prefix/bin prefix/share/contactsweep
cp "$bin" prefix/bin/contactsweep
snapshot=$(dirname "$bin")/kernel_include
cp -r "$snapshot" prefix/share/contactsweep/include
rm -rf cache_s && mkdir -m 0700 cache_s
CONTACTSWEEP_CACHE=$work/cache_s prefix/bin/contactsweep run k.toml -o s1.h5 --quiet 2>stderr
rc1=$?
echo "// edited after the build" >>prefix/share/contactsweep/include/physics/dual_math.hpp
echo 0000 >prefix/share/contactsweep/include/HEADERS_SHA256
rm -rf cache_s && mkdir -m 0700 cache_s
CONTACTSWEEP_CACHE=$work/cache_s prefix/bin/contactsweep run k.toml -o s2.h5 --quiet 2>stderr
rc2=$?
((rc1 == 0 && rc2 == 1)) && same ref.h5 s1.h5 && [[ ! -e s2.h5 ]] && grep -q "not the ones this contactsweep was built with" stderr &&
  ok "kernels compile only against the headers the program was built with (changed snapshot: exit 1)" ||
  bad "headers other than the build's snapshot" "exit $rc1, $rc2"

# ---- 12. a killed run leaves no compiler running, and its debris is cleaned -----------------------
cat >slow_cxx <<EOF
#!/bin/sh
case "\$*" in *--version*) exec g++ --version ;; esac
echo \$\$ >$work/compiler.pid
sleep 60
EOF
chmod +x slow_cxx
rm -rf cache_k && mkdir -m 0700 cache_k compiler.pid 2>/dev/null; rm -rf compiler.pid
CONTACTSWEEP_CXX=$work/slow_cxx CONTACTSWEEP_CACHE=$work/cache_k "$bin" run k.toml -o killed.h5 --quiet 2>stderr &
cs_pid=$!
for _ in $(seq 100); do [[ -s compiler.pid ]] && break; sleep 0.1; done
kill -9 $cs_pid; wait $cs_pid 2>/dev/null
compiler_pid=$(cat compiler.pid 2>/dev/null)
for _ in $(seq 30); do kill -0 "$compiler_pid" 2>/dev/null || break; sleep 0.1; done
if [[ -n $compiler_pid ]] && ! kill -0 "$compiler_pid" 2>/dev/null; then
  ok "the compiler dies with a killed run"
else
  bad "the compiler dies with a killed run" "pid ${compiler_pid:-?} still alive"
  kill -9 "$compiler_pid" 2>/dev/null
fi
stale=$(ls -d cache_k/build.* 2>/dev/null | wc -l)
CONTACTSWEEP_CACHE=$work/cache_k "$bin" run k.toml -o after_kill.h5 --quiet 2>stderr
rc=$?
left=$(ls -d cache_k/build.* 2>/dev/null | wc -l)
((rc == 0 && stale == 1 && left == 0)) && same ref.h5 after_kill.h5 &&
  ok "the killed build's private directory is removed by the next build" ||
  bad "the killed build's private directory is removed" "exit $rc, $stale before, $left after"

# umask 000: the cache and its libraries are still private.
rm -rf cache_u
(umask 000; CONTACTSWEEP_CACHE=$work/cache_u "$bin" run k.toml -o umask.h5 --quiet 2>stderr)
modes=$(stat -c %a cache_u $(ls cache_u/kernel-*.so) | sort -u | tr '\n' ' ')
[[ $modes == "600 700 " || $modes == "700 600 " ]] && ok "under umask 000 the cache is 0700 and its library 0600" ||
  bad "under umask 000" "modes: $modes"

# The cache's parent swapped while the kernel compiles, as another user who can rename a parent
# (of a group-writable project directory, say) would: a link in its place to a tree of theirs,
# whose build directory of the same name holds their source. The compiler runs in the build
# directory it was handed by descriptor, with names relative to it, so it never reads through
# the swapped path. This "compiler" swaps the parent, compiles, then puts the parent back.
rm -rf swap && mkdir -p swap/parent swap/evil/cache && mkdir -m 0700 swap/parent/cache && chmod 0700 swap/evil/cache
cat >swapping_cxx <<EOF
#!/bin/bash
case "\$*" in *--version*) exec g++ --version ;; esac
build=\$(basename "\$(ls -d $work/swap/parent/cache/build.* | head -1)")
mkdir -p $work/swap/evil/cache/\$build
echo '#error "the source planted under the swapped path was compiled"' >$work/swap/evil/cache/\$build/kernel.cpp
mv $work/swap/parent $work/swap/parent.real && ln -s $work/swap/evil $work/swap/parent
g++ "\$@"
rc=\$?
rm $work/swap/parent && mv $work/swap/parent.real $work/swap/parent
exit \$rc
EOF
chmod +x swapping_cxx
CONTACTSWEEP_CXX=$work/swapping_cxx CONTACTSWEEP_CACHE=$work/swap/parent/cache "$bin" run k.toml -o swap.h5 --quiet 2>stderr
rc=$?
((rc == 0)) && same ref.h5 swap.h5 && [[ -n $(ls swap/parent/cache/kernel-*.so 2>/dev/null) ]] &&
  ok "the cache's parent swapped during the build: the planted source is never compiled (same bits)" ||
  bad "the cache's parent swapped during the build" "exit $rc"

# GCC's search variables in the user's environment (a module system may point them at shared
# directories, and the kernel's key does not cover them) do not reach the compiler: an `as`
# planted on COMPILER_PATH and GCC_EXEC_PREFIX, headers on CPATH and CPLUS_INCLUDE_PATH, a
# relative PATH entry.
rm -rf planted && mkdir -p planted/bin planted/include && rm -rf cache_e && mkdir -m 0700 cache_e
printf '#!/bin/sh\necho ran >%s/planted/AS_RAN\nexit 1\n' "$work" >planted/bin/as && chmod +x planted/bin/as
for h in memory cmath; do echo '#error "a header on the include path variables was compiled in"' >planted/include/$h; done
COMPILER_PATH=$work/planted/bin GCC_EXEC_PREFIX=$work/planted/bin/ CPATH=$work/planted/include \
  CPLUS_INCLUDE_PATH=$work/planted/include PATH=".:$PATH" CONTACTSWEEP_CACHE=$work/cache_e \
  "$bin" run k.toml -o env.h5 --quiet 2>stderr
rc=$?
((rc == 0)) && same ref.h5 env.h5 && [[ ! -e planted/AS_RAN ]] &&
  ok "COMPILER_PATH, GCC_EXEC_PREFIX, CPATH and CPLUS_INCLUDE_PATH never reach the compiler (same bits)" ||
  bad "GCC's search variables reach the compiler" "exit $rc"

# The compiler itself named without a slash (CONTACTSWEEP_CXX=g++) is looked up on PATH's
# absolute entries only: `g++ --version` runs in the user's directory (an output's shared one),
# where a relative PATH entry would start the g++ planted there.
rm -rf planted_cwd cache_p && mkdir planted_cwd && mkdir -m 0700 cache_p
printf '#!/bin/sh\necho ran >%s/planted_cwd/CXX_RAN\nexit 1\n' "$work" >planted_cwd/g++ && chmod +x planted_cwd/g++
(cd planted_cwd && PATH=".:$PATH" CONTACTSWEEP_CXX=g++ CONTACTSWEEP_CACHE=$work/cache_p \
  "$bin" run ../k.toml -o ../cwd.h5 --quiet) 2>stderr
rc=$?
((rc == 0)) && same ref.h5 cwd.h5 && [[ ! -e planted_cwd/CXX_RAN ]] &&
  ok "CONTACTSWEEP_CXX=g++ with '.' on PATH never starts a g++ in the current directory (same bits)" ||
  bad "CONTACTSWEEP_CXX=g++ with '.' on PATH" "exit $rc$([[ -e planted_cwd/CXX_RAN ]] && echo ', the planted g++ ran')"

# ---- as other users: a second uid plants, a third runs ------------------------------------------
if ((EUID != 0)) || ! command -v useradd >/dev/null || ! command -v setpriv >/dev/null; then
  skip "cases planted by another user" "needs root to create the users"
  echo "$passed passed, $failed failed, $skipped skipped"
  ((failed == 0)) || exit 1
  exit 77
fi
for u in cs-sec-victim cs-sec-attacker; do
  id -u $u >/dev/null 2>&1 || useradd --system --no-create-home --shell /usr/sbin/nologin $u
done
mkdir -p victim_home && chown cs-sec-victim: victim_home && usermod -d "$work/victim_home" cs-sec-victim
vuid=$(id -u cs-sec-victim) auid=$(id -u cs-sec-attacker)
as() { local u=$1; shift; setpriv --reuid="$(id -u "$u")" --regid="$(id -g "$u")" --clear-groups "$@"; }
shared=$work/shared && mkdir -m 1777 "$shared" && chmod 1777 "$shared"
cp k.toml ref.h5 "$shared/" && chmod 644 "$shared/k.toml" "$shared/ref.h5"

# A planted kernel under the predictable cache of a job without HOME (the old /tmp fallback),
# and in a cache others can write to, with a constructor that leaves a mark: never loaded.
evil=$work/evil.c
cat >"$evil" <<EOF
#include <stdio.h>
__attribute__((constructor)) static void planted(void) { FILE* f = fopen("$shared/PWNED", "w"); if (f) fclose(f); }
EOF
gcc -shared -fPIC -o "$work/evil.so" "$evil"
rm -rf /tmp/.cache/contactsweep.test-planted
as cs-sec-attacker mkdir -m 0777 "$shared/cache" && chmod 0777 "$shared/cache"
as cs-sec-attacker cp "$work/evil.so" "$shared/cache/$(basename "$lib")"
(cd "$shared" && as cs-sec-victim env -u HOME -u XDG_CACHE_HOME CONTACTSWEEP_CACHE="$shared/cache" \
  "$bin" run k.toml -o victim1.h5 --quiet) 2>stderr
rc=$?
((rc == 2)) && [[ ! -e $shared/PWNED && ! -e $shared/victim1.h5 ]] && grep -q "kernel cache" stderr &&
  ok "a kernel cache another user owns is refused (exit 2), the planted library never loaded" ||
  bad "a kernel cache another user owns" "exit $rc"

mkdir -m 0700 "$shared/vcache" && chown cs-sec-victim: "$shared/vcache" && chmod 0777 "$shared/vcache"
as cs-sec-attacker cp "$work/evil.so" "$shared/vcache/$(basename "$lib")"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$shared/vcache" "$bin" run k.toml -o victim2.h5 --quiet) 2>stderr
rc=$?
((rc == 2)) && [[ ! -e $shared/PWNED ]] && grep -q "others can write to it" stderr &&
  ok "the victim's own cache, writable by others, is refused (exit 2) with how to fix it" ||
  bad "a cache others can write to" "exit $rc"

# The victim's private cache holding a library another user owns (root planted it): rebuilt.
chmod 0700 "$shared/vcache" && rm -f "$shared/vcache"/*
cp "$work/evil.so" "$shared/vcache/$(basename "$lib")" && chown cs-sec-attacker: "$shared/vcache/$(basename "$lib")"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$shared/vcache" "$bin" run k.toml -o victim3.h5 --quiet) 2>stderr
rc=$?
((rc == 0)) && [[ ! -e $shared/PWNED ]] && same ref.h5 "$shared/victim3.h5" && grep -q "not to you" stderr &&
  ok "a library another user owns in one's own cache is rebuilt, never loaded (same bits)" ||
  bad "a library another user owns" "exit $rc"

# No HOME: the cache is in the passwd entry's home, not in a directory anyone can create first.
as cs-sec-attacker mkdir -p /tmp/.cache/contactsweep 2>/dev/null
(cd "$shared" && as cs-sec-victim env -u HOME -u XDG_CACHE_HOME -u CONTACTSWEEP_CACHE "$bin" run k.toml -o victim4.h5 --quiet) 2>stderr
rc=$?
((rc == 0)) && same ref.h5 "$shared/victim4.h5" && [[ -n $(ls victim_home/.cache/contactsweep/kernel-*.so 2>/dev/null) ]] &&
  [[ $(stat -c %a victim_home/.cache) == 700 ]] &&
  ok "without HOME the kernel cache is the passwd home's (~/.cache 0700), never /tmp/.cache" ||
  bad "without HOME" "exit $rc"

# Headers planted where an installed program would keep them. The program looks for its headers
# up to 4 directories above itself (PREFIX/share for PREFIX/bin/contactsweep, and for the Python
# module PREFIX/lib/python3.X/dist-packages/contactsweep); for a copy that is not installed, 4
# levels below a shared directory (a build tree in /scratch/you/src/contactsweep/build, or the
# module of a checkout /scratch/contactsweep), that is a directory anyone can create. The
# planted copy has the right HEADERS_SHA256 (any user can read it) and a constructor: never
# compiled in, a warning names it, and the build tree's snapshot is used (same bits).
as cs-sec-victim mkdir -p "$shared/v/src/cs/build" && as cs-sec-victim cp "$bin" "$shared/v/src/cs/build/contactsweep"
as cs-sec-attacker mkdir -p "$shared/share/contactsweep"
as cs-sec-attacker cp -r "$(dirname "$bin")/kernel_include" "$shared/share/contactsweep/include"
as cs-sec-attacker rm -f "$shared/share/contactsweep/include/kernel_build/kernel_prelude.hpp.gch"
as cs-sec-attacker sh -c "cat >>'$shared/share/contactsweep/include/kernel_build/kernel_prelude.hpp'" <<EOF
#include <cstdio>
__attribute__((constructor)) static void planted(void) { if (FILE* f = std::fopen("$shared/PWNED_HEADERS", "w")) std::fclose(f); }
EOF
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$work/victim_home/headers_cache" \
  "$shared/v/src/cs/build/contactsweep" run k.toml -o victim5.h5 --quiet) 2>stderr
rc=$?
((rc == 0)) && [[ ! -e $shared/PWNED_HEADERS ]] && same ref.h5 "$shared/victim5.h5" &&
  grep -q "not compiling kernels against the headers in '$shared/share/contactsweep/include'" stderr &&
  ok "headers another user planted where an installed program's would be are not compiled in (same bits)" ||
  bad "headers planted where an installed program's would be" "exit $rc$([[ -e $shared/PWNED_HEADERS ]] && echo ', the planted code ran')"

# The same place holding another user's link to another installation's headers (root's, of
# another version): the checks see the link's target alone, which is root's, so these headers
# were chosen and every kernel's build failed on their hash ("rebuild it"). The link is passed
# over like a planted directory: a warning names it, the build tree's snapshot is used.
mkdir -m 1777 "$shared/scratch" && chmod 1777 "$shared/scratch"
as cs-sec-victim mkdir -p "$shared/scratch/v/src/cs/build" &&
  as cs-sec-victim cp "$bin" "$shared/scratch/v/src/cs/build/contactsweep"
mkdir -p "$work/other/share/contactsweep" && cp -r "$(dirname "$bin")/kernel_include" "$work/other/share/contactsweep/include"
echo 0000000000000000000000000000000000000000000000000000000000000000 >"$work/other/share/contactsweep/include/HEADERS_SHA256"
chmod -R go-w "$work/other"
as cs-sec-attacker mkdir -p "$shared/scratch/share/contactsweep"
as cs-sec-attacker ln -s "$work/other/share/contactsweep/include" "$shared/scratch/share/contactsweep/include"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$work/victim_home/link_cache" \
  "$shared/scratch/v/src/cs/build/contactsweep" run k.toml -o victim7.h5 --quiet) 2>stderr
rc=$?
((rc == 0)) && same ref.h5 "$shared/victim7.h5" &&
  grep -q "'$shared/scratch/share/contactsweep/include' is a link that user id $auid made" stderr &&
  ok "another user's link to another installation's headers is passed over, the build's own used (same bits)" ||
  bad "another user's link to another installation's headers" "exit $rc"

# The build tree's snapshot is named by its absolute path: a program copied elsewhere (~/bin)
# from a build tree in /tmp that is then removed finds whatever another user makes under that
# name. Played in a private mount namespace, the planted copy bound over the snapshot's path:
# refused (exit 1, nothing written), never compiled in.
snapshot_dir=$(dirname "$bin")/kernel_include
mkdir -p "$shared/copied" && cp "$bin" "$shared/copied/contactsweep" && chmod 755 "$shared/copied/contactsweep"
if unshare -m --propagation private true 2>/dev/null; then
  (cd "$shared" && unshare -m --propagation private sh -c \
    'mount --bind "$1" "$2" && exec setpriv --reuid="$3" --regid="$4" --clear-groups env CONTACTSWEEP_CACHE="$5" "$6" run k.toml -o victim6.h5 --quiet' \
    sh "$shared/share/contactsweep/include" "$snapshot_dir" "$vuid" "$(id -g cs-sec-victim)" \
    "$work/victim_home/snapshot_cache" "$shared/copied/contactsweep") 2>stderr
  rc=$?
  ((rc == 1)) && [[ ! -e $shared/PWNED_HEADERS && ! -e $shared/victim6.h5 ]] &&
    grep -q "not compiling kernels against the headers in '$snapshot_dir': .* belongs to user id $auid" stderr &&
    ok "a snapshot directory another user made under the build tree's name is refused (exit 1), never compiled in" ||
    bad "a snapshot directory another user made under the build tree's name" "exit $rc$([[ -e $shared/PWNED_HEADERS ]] && echo ', the planted code ran')"
else
  skip "a snapshot directory another user made under the build tree's name" "no private mount namespace"
fi

# The build tree's snapshot writable by a group another user is in (a group project's build tree
# under umask 002), the program copied out of it (~/bin): only owners were checked, so that
# user's code (a constructor in the prelude, its precompiled header removed) ran in the victim's
# kernel. Refused (exit 1), naming it. A group of the victim's own (umask 002 with a private
# group, Debian's default) is no one else's: its kernel builds (same bits).
group_snapshot() {  # group_snapshot GROUP: a copy of the snapshot (no precompiled headers), g+w
  rm -rf "$work/group_snapshot" && mkdir "$work/group_snapshot" &&
    tar -C "$snapshot_dir" --exclude='*.gch' -cf - . | tar -C "$work/group_snapshot" -xf - &&
    chgrp -R "$1" "$work/group_snapshot" && chmod -R g+w "$work/group_snapshot"
}
as_victim_with_snapshot() {  # CACHE OUT: the copied program, the group's snapshot bound over the build's
  (cd "$shared" && unshare -m --propagation private sh -c \
    'mount --bind "$1" "$2" && exec setpriv --reuid="$3" --regid="$4" --clear-groups env CONTACTSWEEP_CACHE="$5" "$6" run k.toml -o "$7" --quiet' \
    sh "$work/group_snapshot" "$snapshot_dir" "$vuid" "$(id -g cs-sec-victim)" \
    "$work/victim_home/$1" "$shared/copied/contactsweep" "$2") 2>stderr
}
if unshare -m --propagation private true 2>/dev/null; then
  group_snapshot cs-sec-attacker
  for prelude in kernel_prelude.hpp step_kernel_prelude.hpp; do
    as cs-sec-attacker sh -c "cat >>'$work/group_snapshot/kernel_build/$prelude'" <<EOF
#include <cstdio>
__attribute__((constructor)) static void planted_$RANDOM(void) { if (FILE* f = std::fopen("$shared/PWNED_GROUP", "w")) std::fclose(f); }
EOF
  done
  as_victim_with_snapshot group_cache1 victim8.h5
  rc=$?
  ((rc == 1)) && [[ ! -e $shared/PWNED_GROUP && ! -e $shared/victim8.h5 ]] &&
    grep -q "not compiling kernels against the headers in '$snapshot_dir': others can write to" stderr &&
    ok "a snapshot another user's group can write to is refused (exit 1), never compiled in" ||
    bad "a snapshot another user's group can write to" "exit $rc$([[ -e $shared/PWNED_GROUP ]] && echo ', the planted code ran')"
  if [[ $(id -gn cs-sec-victim) == cs-sec-victim ]]; then
    group_snapshot cs-sec-victim
    as_victim_with_snapshot group_cache2 victim9.h5
    rc=$?
    ((rc == 0)) && same ref.h5 "$shared/victim9.h5" &&
      ok "a snapshot writable by the victim's own private group builds its kernel (same bits)" ||
      bad "a snapshot writable by the victim's own private group" "exit $rc"
  else
    skip "a snapshot writable by the victim's own private group" "useradd made no private group"
  fi
else
  skip "a snapshot another user's group can write to" "no private mount namespace"
fi

# The journal of an output in a shared directory, made first by another user.
as cs-sec-attacker mkdir -m 0700 "$shared/map.h5.journal"
as cs-sec-attacker sh -c "echo mine >'$shared/map.h5.journal/block_0.bin'"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$work/victim_home/.cache/contactsweep" "$bin" run k.toml -o map.h5 --force --quiet) 2>stderr
rc=$?
((rc == 2)) && [[ -f $shared/map.h5.journal/block_0.bin && ! -e $shared/map.h5 ]] && grep -q "belongs to user id $auid" stderr &&
  ok "a journal another user made first is refused (exit 2), its files untouched" ||
  bad "a journal another user made first" "exit $rc"

# Another user's file under the output's name, holding the spec's own text (anyone who can read
# the spec can make one): never taken as the victim's finished run. With --resume it is refused,
# not reported complete; after the victim's run was killed, a plain rerun is refused too, and
# the victim's journal, which "complete" would have removed, stays.
vcache=$work/victim_home/.cache/contactsweep
as cs-sec-attacker cp "$shared/ref.h5" "$shared/forged.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" "$bin" run k.toml -o forged.h5 --resume --quiet) 2>stderr
rc=$?
((rc == 2)) && grep -q "belongs to user id $auid" stderr &&
  ok "--resume over another user's output of the same spec is refused (exit 2), not taken as done" ||
  bad "--resume over another user's output of the same spec" "exit $rc"
big=(--set grid.q_0.n=64 --set grid.p_0.n=16)
"$bin" run k.toml "${big[@]}" -o "$work/big_ref.h5" --quiet 2>stderr || bad "the reference of the interrupted run"
chmod 644 "$work/big_ref.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" CONTACTSWEEP_TEST_KILL=block:2 "$bin" run k.toml "${big[@]}" -o job.h5 --quiet) 2>/dev/null
journal_blocks=$(ls "$shared/job.h5.journal" 2>/dev/null | grep -c block)
as cs-sec-attacker cp "$work/big_ref.h5" "$shared/job.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" "$bin" run k.toml "${big[@]}" -o job.h5 --quiet) 2>stderr
rc=$?
left=$(ls "$shared/job.h5.journal" 2>/dev/null | grep -c block)
((rc == 2 && journal_blocks > 0 && left == journal_blocks)) && grep -q "belongs to user id $auid" stderr &&
  ok "after a killed run, another user's output of the same spec is refused (exit 2), the journal kept ($left blocks)" ||
  bad "another user's output after a killed run" "exit $rc, journal $journal_blocks -> $left blocks"
as cs-sec-attacker rm -f "$shared/job.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" "$bin" run k.toml "${big[@]}" -o job.h5 --resume --quiet) 2>stderr
rc=$?
((rc == 0)) && same "$work/big_ref.h5" "$shared/job.h5" && [[ $(stat -c %u "$shared/job.h5") == "$vuid" ]] &&
  ok "that output moved away, --resume finishes the victim's run from its journal (same bits)" ||
  bad "--resume after the planted output was moved away" "exit $rc"

# --force over another user's output in a sticky directory, where only its owner can replace
# it: refused before the run (exit 2, nothing computed, no journal), not at its commit.
as cs-sec-attacker cp "$shared/ref.h5" "$shared/theirs.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" "$bin" run k.toml -o theirs.h5 --force --quiet) 2>stderr
rc=$?
((rc == 2)) && grep -q "sticky" stderr && [[ ! -e $shared/theirs.h5.journal && $(stat -c %u "$shared/theirs.h5") == "$auid" ]] &&
  ok "--force over another user's output in a sticky directory is refused before the run (exit 2)" ||
  bad "--force over another user's output in a sticky directory" "exit $rc"

# Another user's link as OUT.h5.partial in a sticky directory: the victim cannot remove it, so
# the run is refused; the link's target (the victim's own file) is untouched.
as cs-sec-victim sh -c "echo keep >'$shared/victim_file'"
as cs-sec-attacker ln -s "$shared/victim_file" "$shared/out2.h5.partial"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$work/victim_home/.cache/contactsweep" "$bin" run k.toml -o out2.h5 --quiet) 2>stderr
rc=$?
((rc == 1)) && [[ $(cat "$shared/victim_file") == keep && ! -e $shared/out2.h5 ]] &&
  ok "another user's link as OUT.h5.partial is refused (exit 1), its target untouched" ||
  bad "another user's link as OUT.h5.partial" "exit $rc"

# Another user's dangling link at the output's name, its target holding escape sequences: the
# refusal names the target with its control characters written out, never sends them raw to
# the victim's terminal (a window title set, the screen cleared).
as cs-sec-attacker ln -s "$(printf 'gone\033]0;planted title\007\033[2J')" "$shared/escape.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" "$bin" run k.toml -o escape.h5 --quiet) 2>stderr
rc=$?
((rc == 2)) && ! grep -q $'\033' stderr && grep -qF 'gone\x1b]0;planted title\x07' stderr &&
  ok "a planted link's target reaches the terminal with its control characters written out (exit 2)" ||
  bad "a planted link's target with escape sequences" "exit $rc$(grep -q $'\033' stderr && echo ', raw escapes printed')"
# The same with the C1 control CSI (U+009B, which a UTF-8 terminal takes for ESC [) encoded in
# UTF-8, and as the raw byte an 8-bit terminal takes for it; a name's own UTF-8 (ü) stays.
as cs-sec-attacker ln -s "$(printf 'gone\xc2\x9b2J \x9b2J \xc3\xbc')" "$shared/escape_c1.h5"
(cd "$shared" && as cs-sec-victim env CONTACTSWEEP_CACHE="$vcache" "$bin" run k.toml -o escape_c1.h5 --quiet) 2>stderr
rc=$?
((rc == 2)) && ! LC_ALL=C grep -q $'\x9b' stderr && grep -qF "gone\\xc2\\x9b2J \\x9b2J $(printf '\xc3\xbc')" stderr &&
  ok "a planted link's target reaches the terminal with its C1 controls written out, its UTF-8 kept (exit 2)" ||
  bad "a planted link's target with C1 controls" "exit $rc$(LC_ALL=C grep -q $'\x9b' stderr && echo ', raw CSI printed')"

# Without /proc (a container or chroot that does not mount it) the descriptor a kernel was
# checked on has no name to load it by, and its path is not loaded instead: whoever can rename a
# parent of the cache (here a directory of the attacker's that holds the victim's cache) swaps
# the cache for a link to their copy between the check and the load. Played through the Python
# module (the program cannot link a kernel without /proc anyway) in a private mount namespace
# with /proc hidden. A shim on dlopen makes the swap just before the loader opens a path in the
# cache, as the attacker's loop of renames did once in about 60 runs: refused, saying why, the
# planted library never loaded.
module=$(dirname "$bin")/python
if [[ ! -f $module/contactsweep/__init__.py ]]; then
  skip "a kernel loaded without /proc" "no Python module beside the program"
elif ! unshare -m --propagation private true 2>/dev/null; then
  skip "a kernel loaded without /proc" "no private mount namespace"
else
  cat >"$work/swap_at_dlopen.c" <<'EOF'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <linux/fs.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>
// The attacker's rename wins the race: SWAP_CACHE and their link SWAP_LINK exchanged just
// before a path inside SWAP_CACHE is loaded.
void* dlopen(const char* file, int mode) {
  void* (*real)(const char*, int) = (void* (*)(const char*, int))dlsym(RTLD_NEXT, "dlopen");
  const char *cache = getenv("SWAP_CACHE"), *link = getenv("SWAP_LINK");
  if (file && cache && link && strncmp(file, cache, strlen(cache)) == 0 && file[strlen(cache)] == '/')
    syscall(SYS_renameat2, AT_FDCWD, cache, AT_FDCWD, link, RENAME_EXCHANGE);
  return real(file, mode);
}
EOF
  gcc -shared -fPIC -o "$work/swap_at_dlopen.so" "$work/swap_at_dlopen.c" -ldl
  proj=$shared/proj && as cs-sec-attacker mkdir -m 0777 "$proj" && chmod 0777 "$proj"
  without_proc() {  # without_proc ENV...: the victim's contactsweep.run of k.toml, /proc hidden
    (cd "$shared" && unshare -m --propagation private sh -c \
      'mount -t tmpfs none /proc && u=$1 g=$2 && shift 2 && exec setpriv --reuid="$u" --regid="$g" --clear-groups "$@"' \
      sh "$vuid" "$(id -g cs-sec-victim)" env PYTHONPATH="$module" PYTHONDONTWRITEBYTECODE=1 \
      CONTACTSWEEP_CACHE="$proj/cache" OMP_NUM_THREADS=1 "$@" /usr/bin/python3 -c \
      'import contactsweep; contactsweep.run("k.toml", progress=False)')
  }
  without_proc 2>stderr  # builds the kernel of this key (the CPU is not known without /proc)
  as cs-sec-attacker mkdir -m 0755 "$proj/theirs"
  planted=0
  for built in "$proj"/cache/kernel-*.so; do
    [[ -f $built ]] && as cs-sec-attacker cp "$work/evil.so" "$proj/theirs/${built##*/}" && planted=$((planted + 1))
  done
  as cs-sec-attacker ln -s theirs "$proj/swapped"
  without_proc LD_PRELOAD="$work/swap_at_dlopen.so" SWAP_CACHE="$proj/cache" SWAP_LINK="$proj/swapped" 2>stderr
  rc=$?
  ((rc != 0 && planted > 0)) && [[ ! -e $shared/PWNED ]] &&
    grep -q "/proc must be mounted" stderr &&
    ok "without /proc a kernel is refused, not loaded by its path (a parent swapped meanwhile)" ||
    bad "a kernel loaded without /proc" "exit $rc$([[ -e $shared/PWNED ]] && echo ', the planted code ran')"
fi

# The example's figure, drawn in the user's directory (a shared one, say): another user's file or
# FIFO left at basins.png is refused, naming it; their file was written into (theirs to change
# later), their FIFO waited on forever (or handed the figure).
if [[ ! -f $module/contactsweep/__init__.py ]]; then
  skip "the example's figure over another user's file or FIFO" "no Python module beside the program"
elif ! /usr/bin/python3 -c 'import matplotlib, xarray, h5netcdf' 2>/dev/null; then
  skip "the example's figure over another user's file or FIFO" "no matplotlib, xarray or h5netcdf"
else
  quickstart() {  # the victim's examples/quickstart.py in the shared directory
    (cd "$shared" && as cs-sec-victim env HOME="$work/victim_home" PYTHONPATH="$module" \
      CONTACTSWEEP_CACHE="$vcache" timeout 120 /usr/bin/python3 "$source_dir/examples/quickstart.py") 2>"$work/stderr"
  }
  as cs-sec-attacker sh -c "echo theirs >'$shared/basins.png' && chmod 666 '$shared/basins.png'"
  quickstart
  rc=$?
  ((rc != 0 && rc != 124)) && [[ $(cat "$shared/basins.png") == theirs ]] && grep -q "cannot write basins.png" stderr &&
    ok "the example's figure is not written into another user's file at its name (refused, naming it)" ||
    bad "the example's figure over another user's file" "exit $rc, their file: $(head -c 8 "$shared/basins.png" | tr -c '[:print:]' .)"
  as cs-sec-attacker rm -f "$shared/basins.png" && as cs-sec-attacker mkfifo -m 666 "$shared/basins.png"
  quickstart
  rc=$?
  ((rc != 0 && rc != 124)) && [[ -p $shared/basins.png ]] && grep -q "cannot write basins.png" stderr &&
    ok "the example's figure does not wait on another user's FIFO at its name (refused, naming it)" ||
    bad "the example's figure over another user's FIFO" "exit $rc$( ((rc == 124)) && echo ', it hung')"
  as cs-sec-attacker rm -f "$shared/basins.png"
fi

# jobs/accuracy_charts.sh copies its PNGs into FIGURES_DIR, which may be a shared place: a link
# another user left at a PNG's name is not written through (cp followed it into the victim's
# file). The job runs from a copy of the script beside stub charts (the real ones take minutes).
charts=$work/charts_repo && mkdir -p "$charts/jobs" "$charts/src/post"
cp "$source_dir/jobs/accuracy_charts.sh" "$source_dir/jobs/machine_facts.sh" "$charts/jobs/"
for script in stability_maps:stability_h_gamma,stability_h_q0 \
  work_precision:workprecision_damped_oscillator,workprecision_double_well,basin_accuracy,basin_accuracy_magnetic_pendulum; do
  cat >"$charts/src/post/${script%%:*}.py" <<EOF
import sys, pathlib
out = pathlib.Path(sys.argv[sys.argv.index("--out") + 1])
for name in "${script#*:}".split(","):
    (out / (name + ".png")).write_bytes(b"a chart")
EOF
done
chown -R cs-sec-victim: "$charts"
as cs-sec-victim sh -c "echo keep >'$work/victim_home/precious'"
as cs-sec-attacker ln -s "$work/victim_home/precious" "$shared/stability_h_q0.png"
as cs-sec-victim env HOME="$work/victim_home" FIGURES_DIR="$shared" CONTACTSWEEP_BIN=/bin/true \
  bash "$charts/jobs/accuracy_charts.sh" >/dev/null 2>stderr
rc=$?
((rc != 0)) && [[ $(cat "$work/victim_home/precious") == keep && -L $shared/stability_h_q0.png ]] &&
  grep -q "stability_h_q0.png" stderr &&
  ok "accuracy_charts.sh copies no figure through another user's link in a sticky FIGURES_DIR (refused, naming it)" ||
  bad "accuracy_charts.sh copies through another user's link" "exit $rc, the victim's file: $(head -c 8 "$work/victim_home/precious")"
as cs-sec-attacker mkdir -m 0777 "$shared/figures" && as cs-sec-attacker chmod 0777 "$shared/figures" &&
  as cs-sec-attacker ln -s "$work/victim_home/precious" "$shared/figures/basin_accuracy.png"
as cs-sec-victim env HOME="$work/victim_home" FIGURES_DIR="$shared/figures" CONTACTSWEEP_BIN=/bin/true \
  bash "$charts/jobs/accuracy_charts.sh" >/dev/null 2>stderr
rc=$?
((rc == 0)) && [[ $(cat "$work/victim_home/precious") == keep && ! -L $shared/figures/basin_accuracy.png ]] &&
  [[ $(cat "$shared/figures/basin_accuracy.png") == "a chart" ]] &&
  ok "accuracy_charts.sh replaces another user's link in their FIGURES_DIR, its target untouched" ||
  bad "accuracy_charts.sh over another user's link in their directory" "exit $rc, the victim's file: $(head -c 8 "$work/victim_home/precious")"

echo "$passed passed, $failed failed, $skipped skipped"
((failed == 0))
