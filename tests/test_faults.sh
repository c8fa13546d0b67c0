#!/usr/bin/env bash
# Fault injection, end to end (issue 13): every way a batch job can go wrong that we know of must
# end with a clear message and the right exit status — never a wrong file with exit 0, never a
# hang, never a lost finished block — and --resume must then give the uninterrupted run's bits.
#   test_faults.sh CONTACTSWEEP FAIL_WRITES_SO COMPARE_SCRIPT WORKDIR [LONG_T_END]
# FAIL_WRITES_SO is tests/fault/fail_writes.c built as a shared object (LD_PRELOAD: writes to
# chosen files fail with ENOSPC after N bytes). LONG_T_END sets the length of the runs that other
# processes interfere with while they live (~2 s in a release build).
# Last line: "N passed, M failed, K skipped". Exit status: 1 if any failed; else 77 (CTest's
# SKIP_RETURN_CODE) if a case could not run here — the tmpfs cases need root (as root, CI, they
# must run), the rankfile case cores 0 and 1 — else 0.
set -uo pipefail
bin=$(realpath "$1") shim=$(realpath "$2") compare=$(realpath "$3") work=$4 long_t_end=${5:-3000}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
# The shim is not the first library of a sanitized binary; ASan need not insist on it.
export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0
mpirun=(mpirun --oversubscribe --bind-to none)
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
trap 'mountpoint -q "$work/small" && umount "$work/small"' EXIT

cat >spec.toml <<'EOF'
[scene]
name = "double_well"
[integrator]
h = 0.01
t_end = 20.0
[grid]
q_0 = { from = -3.0, to = 3.0, n = 131 }
p_0 = { from = -3.0, to = 3.0, n = 127 }
[measures]
basin = { early_stop = false }
final_state = { vars = ["q", "p"] }
EOF
long=(--set "integrator.t_end=$long_t_end")  # the same grid, integrated for a few seconds

passed=0 failed=0 skipped=0
ok() { echo "ok    $1"; passed=$((passed + 1)); }
bad() { echo "FAIL  $1: $2"; failed=$((failed + 1)); }
skip() { echo "skip  $1: $2"; skipped=$((skipped + 1)); }
# same NAME OUT REFERENCE: OUT exists, no journal or temporary is left, and its data equal REFERENCE.
same() {
  local leftovers
  leftovers=$(ls -d "$2".journal "$2".partial* 2>/dev/null)
  if [[ ! -f $2 ]]; then bad "$1" "no output $2"; return 1; fi
  if [[ -n $leftovers ]]; then bad "$1" "leftovers: $leftovers"; return 1; fi
  local why
  if ! why=$(/usr/bin/python3 "$compare" "$3" "$2" 2>&1); then bad "$1" "$why"; return 1; fi
  return 0
}
# status NAME EXPECTED ACTUAL LOG FRAGMENT: exit status and message.
status_and_message() {
  if (($3 != $2)); then bad "$1" "exit status $3, expected $2; log: $(tr '\n' ' ' <"$4" | cut -c1-400)"; return 1; fi
  if ! grep -qF -- "$5" "$4"; then bad "$1" "the log lacks '$5': $(tr '\n' ' ' <"$4" | cut -c1-400)"; return 1; fi
  return 0
}
blocks_in() { ls "$1".journal 2>/dev/null | grep -c '^block_.*\.bin$'; }
wait_for_blocks() {  # wait_for_blocks OUT N: until the run on OUT has journaled N blocks (<= 60 s)
  for _ in $(seq 600); do (($(blocks_in "$1") >= $2)) && return 0; sleep 0.1; done
  return 1
}

"$bin" run spec.toml -o reference.h5 --quiet || { echo "reference run failed"; exit 1; }
"$bin" run spec.toml -o long_reference.h5 --quiet "${long[@]}" || { echo "long reference failed"; exit 1; }

# 1. Ranks with different thread counts deal the same blocks: every cell is computed once.
"${mpirun[@]}" -np 1 -x OMP_NUM_THREADS=1 "$bin" run spec.toml -o het.h5 --quiet : \
  -np 1 -x OMP_NUM_THREADS=2 "$bin" run spec.toml -o het.h5 --quiet >het.log 2>&1
rc=$?
if ((rc != 0)); then bad "ranks with 1 and 2 threads" "exit $rc: $(tail -3 het.log)"
elif same "ranks with 1 and 2 threads" het.h5 reference.h5; then ok "ranks with 1 and 2 threads (MPMD): every cell, the 1-process bits"; fi
printf 'rank 0=localhost slot=0\nrank 1=localhost slot=0-1\n' >rankfile
if ! taskset -c 0,1 true 2>/dev/null; then
  skip "rankfile with 1 and 2 cores per rank" "this process may not run on cores 0 and 1"
elif (env -u OMP_NUM_THREADS mpirun -np 2 --rankfile rankfile "$bin" run spec.toml -o rankfile.h5 \
      --quiet >rankfile.log 2>&1); then
  same "rankfile: 1 and 2 cores" rankfile.h5 reference.h5 && ok "rankfile with 1 and 2 cores per rank: the 1-process bits" ||
  bad "rankfile with 1 and 2 cores per rank: the 1-process bits" "a step of this case failed without its own message (see the logs in the work directory)"
else
  bad "rankfile: 1 and 2 cores" "$(tail -3 rankfile.log)"
fi

# 1b. A rank far slower than rank 0: rank 1 stops itself (SIGSTOP, the test hook) after its first
# saved block, and goes on only once rank 0 has journalled all of its own blocks and has nothing
# left to compute. Rank 0 must wait for every block it is sent before it writes the file: had it
# stopped listening early, rank 1's later blocks were lost (their cells left at the fill value)
# or rank 1 hung in its sends.
CONTACTSWEEP_TEST_KILL=block:1@1/stop timeout 120 "${mpirun[@]}" -np 2 -x CONTACTSWEEP_TEST_KILL \
  "$bin" run spec.toml -o slow_rank.h5 --quiet >slow_rank.log 2>&1 &
job=$!
stopped=""
for _ in $(seq 600); do  # rank 1 stopped (state T), up to 60 s
  for pid in $(pgrep -P "$job" 2>/dev/null; pgrep -P "$(pgrep -P "$job" | head -1)" 2>/dev/null); do
    [[ $(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null) == T ]] && stopped=$pid
  done
  [[ -n $stopped ]] && break
  sleep 0.1
done
if [[ -z $stopped ]]; then
  kill "$job" 2>/dev/null; wait "$job"
  bad "a slow rank: rank 1 never stopped" "$(tail -3 slow_rank.log)"
else
  # Rank 0 is done with its own blocks once the journal stops growing while rank 1 is stopped.
  last=-1
  for _ in $(seq 600); do
    now=$(blocks_in slow_rank.h5)
    ((now == last)) && break
    last=$now
    sleep 1
  done
  kill -CONT "$stopped"
  wait "$job"
  rc=$?
  if ((rc != 0)); then bad "a slow rank" "exit $rc: $(tail -3 slow_rank.log)"
  elif same "a slow rank" slow_rank.h5 reference.h5; then
    ok "a rank stopped until rank 0 had finished ($last blocks journalled by then): rank 0 waited for its blocks, the 1-process bits"
  fi
fi
# 2a. A journal from another build is never mixed in: refused, with the build named.
CONTACTSWEEP_TEST_KILL=block:3 "$bin" run spec.toml -o build.h5 --quiet 2>/dev/null
sed -i 's/^run .*/run 0123456789abcdef/; s/^build .*/build 0.1.0 build-id 00ff/' build.h5.journal/manifest
"$bin" run spec.toml -o build.h5 --resume --quiet >build.log 2>&1
status_and_message "journal of another build" 2 $? build.log "another build of contactsweep" &&
  [[ ! -e build.h5 ]] && ok "a journal left by another build is refused (exit 2), not resumed" ||
  bad "a journal left by another build is refused (exit 2), not resumed" "a step of this case failed without its own message (see the logs in the work directory)"
# ...and one of the old format, which did not identify its build at all.
mkdir -p old.h5.journal && printf 'contactsweep journal\nversion 0.1.0\npoints 16637\n' >old.h5.journal/manifest
cp build.h5.journal/block_0.bin old.h5.journal/
"$bin" run spec.toml -o old.h5 --resume --quiet >old.log 2>&1
status_and_message "journal of the old format" 2 $? old.log "older contactsweep" &&
  ok "an old-format journal is refused (exit 2)" ||
  bad "an old-format journal is refused (exit 2)" "a step of this case failed without its own message (see the logs in the work directory)"
"$bin" run spec.toml -o old.h5 --force --quiet && same "old journal discarded with --force" old.h5 reference.h5 &&
  ok "--force discards it and computes afresh" ||
  bad "--force discards it and computes afresh" "a step of this case failed without its own message (see the logs in the work directory)"

# 2b. A second run on an output whose run is alive is refused; the first finishes untouched.
"$bin" run spec.toml -o live.h5 --quiet "${long[@]}" 2>live_a.log &
run_a=$!
if wait_for_blocks live.h5 1; then
  "$bin" run spec.toml -o live.h5 --force --quiet --set scene.gamma=0.2 >live_b.log 2>&1
  status_and_message "second run on a live output" 2 $? live_b.log "another run is writing this output" &&
    ok "a second run (--force, another spec) on a live run's output is refused (exit 2)" ||
  bad "a second run (--force, another spec) on a live run's output is refused (exit 2)" "a step of this case failed without its own message (see the logs in the work directory)"
  "$bin" run spec.toml -o live.h5 --resume --quiet "${long[@]}" >live_c.log 2>&1
  status_and_message "resume of a live run" 2 $? live_c.log "another run is writing this output" &&
    ok "--resume of a run that is still alive is refused (exit 2)" ||
  bad "--resume of a run that is still alive is refused (exit 2)" "a step of this case failed without its own message (see the logs in the work directory)"
else
  bad "second run on a live output" "the first run journaled no block within 60 s"
fi
wait "$run_a"
rc=$?
((rc == 0)) && same "the live run after the refusals" live.h5 long_reference.h5 &&
  ok "the live run ends with exit 0 and its own bits" ||
  bad "the live run ends with exit 0 and its own bits" "a step of this case failed without its own message (see the logs in the work directory)"

# 2c. A run that made the journal's directory but lost its lock to another run (both started at
# once) is refused and leaves the live run's lock alone: it once removed it on its way out, so a
# third run locked a fresh file beside the live one, and a live run then put the third's
# half-written file in place with exit 0. strace holds the first run for 1.5 s between its
# mkdir of the journal and its lock, so that the second takes the lock first. The second stops
# itself (SIGSTOP, the test hook) after its first saved block, so that it is alive, whatever the
# machine's load, when the third starts; it goes on once the third has been refused.
if command -v strace >/dev/null && strace -f -qq -o /dev/null true 2>/dev/null; then
  rm -rf steal.h5*
  strace -f -qq -o /dev/null -P steal.h5.journal -e trace=mkdir -e inject=mkdir:delay_exit=1500000 \
    "$bin" run spec.toml -o steal.h5 --quiet "${long[@]}" >steal_x.log 2>&1 &
  run_x=$!
  sleep 0.5
  CONTACTSWEEP_TEST_KILL=block:1/stop "$bin" run spec.toml -o steal.h5 --quiet "${long[@]}" \
    >steal_y.log 2>&1 &
  run_y=$!
  wait "$run_x"
  rc_x=$?
  lock_left=$([[ -f steal.h5.journal/lock ]] && echo yes || echo no)
  for _ in $(seq 600); do  # the live run stopped (state T), up to 60 s
    [[ $(awk '{print $3}' "/proc/$run_y/stat" 2>/dev/null) == T ]] && break
    sleep 0.1
  done
  "$bin" run spec.toml -o steal.h5 --resume --quiet "${long[@]}" >steal_z.log 2>&1
  rc_z=$?
  kill -CONT "$run_y"
  wait "$run_y"
  rc_y=$?
  if status_and_message "the run that lost the lock" 2 $rc_x steal_x.log "another run is writing this output" &&
     [[ $lock_left == yes ]] &&
     status_and_message "a third run beside the live one" 2 $rc_z steal_z.log "another run is writing this output" &&
     ((rc_y == 0)) && same "the live run beside two refused ones" steal.h5 long_reference.h5; then
    ok "a run that made the journal but lost its lock leaves the live run's lock; a third is refused; the live run's bits"
  elif [[ $lock_left != yes ]]; then
    bad "a run that lost the lock" "the live run's lock file was removed (exits: $rc_x, $rc_z, $rc_y)"
  fi
else
  skip "a run that made the journal but lost its lock" "needs strace (with ptrace allowed)"
fi

# Damaged journal files that are no block at all: a FIFO under a block's name (opening it once
# waited forever) and a block extended to a terabyte (sparse; its size was allocated: bad_alloc,
# and the resume was blocked). Both are recomputed: exit 0, the uninterrupted run's bits.
for damage in fifo huge; do
  rm -rf "odd_$damage.h5"*
  CONTACTSWEEP_TEST_KILL=block:3 "$bin" run spec.toml -o "odd_$damage.h5" --quiet 2>/dev/null
  first=$(ls "odd_$damage.h5.journal" 2>/dev/null | grep '^block_.*\.bin$' | head -1)
  if [[ -z $first ]]; then bad "a $damage in the journal" "the killed run journaled no block"; continue; fi
  if [[ $damage == fifo ]]; then
    rm "odd_$damage.h5.journal/$first" && mkfifo "odd_$damage.h5.journal/$first"
  else
    truncate -s 1T "odd_$damage.h5.journal/$first"
  fi
  timeout 120 "$bin" run spec.toml -o "odd_$damage.h5" --resume --quiet >"odd_$damage.log" 2>&1
  rc=$?
  ((rc == 0)) && same "a $damage in the journal" "odd_$damage.h5" reference.h5 &&
    ok "a $damage under a journal block's name: --resume recomputes it (exit 0, the right bits)" ||
    { ((rc != 0)) && bad "a $damage under a journal block's name" "exit $rc (124: hung): $(head -c 300 "odd_$damage.log")"; }
done

# 3. Disk full while the HDF5 file is written (after 0 bytes, mid-metadata, mid-data), on one
# rank, on both, and on rank 0 of two only: exit 1 with a message, no temporary, journal kept,
# and --resume gives the right file.
fault=(-x "LD_PRELOAD=$shim" -x CONTACTSWEEP_FAULT_PATH=.h5.partial)
for after in 0 40000 300000; do
  out=full_$after.h5
  env LD_PRELOAD="$shim" CONTACTSWEEP_FAULT_PATH=.h5.partial CONTACTSWEEP_FAULT_AFTER=$after \
    timeout 120 "$bin" run spec.toml -o "$out" --quiet >"$out.log" 2>&1
  rc=$?
  if status_and_message "full disk in the HDF5 write after $after bytes" 1 $rc "$out.log" "cannot" &&
     [[ ! -e $out && ! -e $out.partial && -d $out.journal ]]; then
    "$bin" run spec.toml -o "$out" --resume --quiet && same "resume after a full disk" "$out" reference.h5 &&
      ok "full disk in the HDF5 write after $after bytes: exit 1, journal kept, resumed to the right bits" ||
  bad "full disk in the HDF5 write after $after bytes: exit 1, journal kept, resumed to the right bits" "a step of this case failed without its own message (see the logs in the work directory)"
  elif ((rc == 1)); then bad "full disk after $after bytes" "left: $(ls -d "$out"* | tr '\n' ' ')"; fi
  for who in both rank0; do
    out=full_${after}_np2_$who.h5
    if [[ $who == both ]]; then
      timeout 120 "${mpirun[@]}" -np 2 "${fault[@]}" -x CONTACTSWEEP_FAULT_AFTER=$after "$bin" run \
        spec.toml -o "$out" --quiet >"$out.log" 2>&1
    else
      timeout 120 "${mpirun[@]}" -np 1 "${fault[@]}" -x CONTACTSWEEP_FAULT_AFTER=$after "$bin" run \
        spec.toml -o "$out" --quiet : -np 1 "$bin" run spec.toml -o "$out" --quiet >"$out.log" 2>&1
    fi
    rc=$?
    if ((rc == 124)); then bad "full disk, 2 ranks ($who), after $after bytes" "hang (killed after 120 s)"; continue; fi
    if ((rc != 0)) && grep -qF "contactsweep: run-time failure" "$out.log" &&
       [[ ! -e $out && ! -e $out.partial && -d $out.journal ]]; then
      "${mpirun[@]}" -np 2 "$bin" run spec.toml -o "$out" --resume --quiet &&
        same "resume after a full disk on 2 ranks" "$out" reference.h5 &&
        ok "full disk in the HDF5 write on 2 ranks ($who) after $after bytes: no hang, exit $rc, resumed" ||
  bad "full disk in the HDF5 write on 2 ranks ($who) after $after bytes: no hang, exit $rc, resumed" "a step of this case failed without its own message (see the logs in the work directory)"
    else
      bad "full disk, 2 ranks ($who), after $after bytes" "exit $rc, left $(ls -d "$out"* | tr '\n' ' '): $(grep contactsweep "$out.log" | head -2)"
    fi
  done
done
# A real full disk: a tmpfs that holds the journal but not the file as well is refused up front.
mkdir -p small
if ((EUID != 0)); then
  skip "tmpfs cases (a disk too small for file and journal; --resume on a full disk)" "mounting needs root"
elif ! mount -t tmpfs -o size=600k tmpfs small 2>small_mount.log; then
  bad "tmpfs cases" "root cannot mount a tmpfs: $(cat small_mount.log)"
else
  "$bin" run spec.toml -o small/a.h5 --quiet >small.log 2>&1
  status_and_message "output and journal larger than the disk" 2 $? small.log "journal" &&
    [[ -z $(ls small) ]] && ok "a disk with room for the file but not for the journal too: refused (exit 2), nothing written" ||
  bad "a disk with room for the file but not for the journal too: refused (exit 2), nothing written" "a step of this case failed without its own message (see the logs in the work directory)"
  # A finished output on a full disk: --resume says it is complete (no resource check first).
  cp reference.h5 small/done.h5 && dd if=/dev/zero of=small/filler bs=4k 2>/dev/null
  "$bin" run spec.toml -o small/done.h5 --resume --quiet &&
    ok "--resume of a finished output on a full disk: exit 0" || bad "resume of a finished output on a full disk" "exit $?"
  umount small
fi

# A quota the free-space figures do not show (the shim refuses the file's reservation with
# EDQUOT; its writes pass): refused before any block is computed, exit 1 naming the quota, no
# output or temporary; once there is room, --resume writes the uninterrupted run's bits.
env LD_PRELOAD="$shim" CONTACTSWEEP_FAULT_PATH=.h5.partial CONTACTSWEEP_FAULT_RESERVE=0 \
  CONTACTSWEEP_FAULT_AFTER=1000000000000 CONTACTSWEEP_FAULT_ERRNO=122 timeout 120 "$bin" run spec.toml -o quota.h5 --quiet >quota.log 2>&1
rc=$?
if status_and_message "a quota too small for the output" 1 $rc quota.log "do not fit on its disk: Disk quota exceeded" &&
   [[ ! -e quota.h5 && ! -e quota.h5.partial ]] && (($(blocks_in quota.h5) == 0)) &&
   "$bin" run spec.toml -o quota.h5 --resume --quiet && same "resume after the quota" quota.h5 reference.h5; then
  ok "a quota too small for the output: refused before computing (exit 1), resumed to the right bits"
elif ((rc == 1)); then
  bad "a quota too small for the output" "left: $(ls -d quota.h5* | tr '\n' ' '), $(blocks_in quota.h5) blocks journalled"
fi

# A file system without locks (an NFS mount without lockd; the shim fails the journal's lock
# with ENOLCK): the run goes on with a warning, and a start refused there (an output that
# exists, no --force) leaves no journal either; it used to leave the directory it made, with
# its lock file.
env LD_PRELOAD="$shim" CONTACTSWEEP_FAULT_LOCK=.journal/lock "$bin" run spec.toml -o nolock.h5 --quiet >nolock.log 2>&1
status_and_message "a run on a file system without locks" 0 $? nolock.log "cannot lock files" &&
  same "a run on a file system without locks" nolock.h5 reference.h5 &&
  ok "a run on a file system without locks: a warning, the right bits, no journal left"
env LD_PRELOAD="$shim" CONTACTSWEEP_FAULT_LOCK=.journal/lock "$bin" run spec.toml -o nolock.h5 --quiet >nolock_refused.log 2>&1
rc=$?
if status_and_message "a refused start without locks" 2 $rc nolock_refused.log "pass --force" &&
   [[ ! -e nolock.h5.journal ]]; then
  ok "a start refused on a file system without locks leaves no journal"
elif ((rc == 2)); then
  bad "a start refused on a file system without locks" "left: $(ls -A nolock.h5.journal 2>&1 | tr '\n' ' ')"
fi

# 4. Bad input seen by only some ranks: every rank exits 2, rank 0 says why, no hang.
timeout 120 "${mpirun[@]}" -np 1 "$bin" run spec.toml -o budget.h5 : \
  -np 1 -x CONTACTSWEEP_MEMORY_LIMIT=64K "$bin" run spec.toml -o budget.h5 >budget.log 2>&1
rc=$?
status_and_message "memory budget on rank 1 only" 2 $rc budget.log "rank 1" &&
  [[ ! -e budget.h5 && ! -e budget.h5.journal ]] && ok "a budget only rank 1 fails: every rank exits 2, rank 0 names rank 1, nothing written" ||
  bad "a budget only rank 1 fails: every rank exits 2, rank 0 names rank 1, nothing written" "a step of this case failed without its own message (see the logs in the work directory)"
# A spec only rank 0 can read (mpirun gives stdin to rank 0 alone): it is broadcast.
timeout 120 "${mpirun[@]}" -np 2 "$bin" run /dev/stdin -o stdin.h5 --quiet <spec.toml >stdin.log 2>&1
rc=$?
((rc == 0)) && same "spec from /dev/stdin under mpirun" stdin.h5 reference.h5 &&
  ok "a spec on /dev/stdin under mpirun -np 2: read by rank 0, the right file" ||
  bad "a spec on /dev/stdin under mpirun -np 2: read by rank 0, the right file" "a step of this case failed without its own message (see the logs in the work directory)"
((rc == 0)) || bad "spec from /dev/stdin under mpirun" "exit $rc: $(tail -2 stdin.log)"

# 5. A failed save stops the run at once, on every rank, and leaves no temporary files. The
# long run has 65 blocks; a save fails after ~2 blocks' bytes, on the only rank, then on rank 1
# of 2 (rank 0's disk is fine: it must stop because rank 1 failed). Rank 0 learns of it within
# two rounds of the failure watch, a few blocks; without the stop it saved ~63.
for ranks in 1 2; do
  out=save_np$ranks.h5
  failing=(-x "LD_PRELOAD=$shim" -x CONTACTSWEEP_FAULT_PATH=.bin.tmp -x CONTACTSWEEP_FAULT_AFTER=25000)
  if ((ranks == 1)); then
    timeout 120 "${mpirun[@]}" -np 1 "${failing[@]}" "$bin" run spec.toml -o "$out" --quiet "${long[@]}" >"$out.log" 2>&1
  else
    timeout 120 "${mpirun[@]}" -np 1 "$bin" run spec.toml -o "$out" --quiet "${long[@]}" : \
      -np 1 "${failing[@]}" "$bin" run spec.toml -o "$out" --quiet "${long[@]}" >"$out.log" 2>&1
  fi
  rc=$?
  saved=$(blocks_in "$out")
  tmps=$(ls "$out".journal 2>/dev/null | grep -c '\.tmp$')
  if ((rc == 124)); then bad "failed save, $ranks rank(s)" "hang"
  elif ((rc == 0)); then bad "failed save, $ranks rank(s)" "exit 0"
  elif ((tmps > 0)); then bad "failed save, $ranks rank(s)" "$tmps .tmp files left"
  elif ((saved > 16)); then bad "failed save, $ranks rank(s)" "$saved of 65 blocks saved: the run went on after the failure"
  elif ! grep -qF "cannot write" "$out.log"; then bad "failed save, $ranks rank(s)" "no message: $(tail -2 "$out.log")"
  else
    "$bin" run spec.toml -o "$out" --resume --quiet "${long[@]}" && same "resume after a failed save" "$out" long_reference.h5 &&
      ok "a failed save on $ranks rank(s) stops every rank ($saved of 65 blocks saved), no .tmp left, resumed" ||
  bad "a failed save on $ranks rank(s) stops every rank ($saved of 65 blocks saved), no .tmp left, resumed" "a step of this case failed without its own message (see the logs in the work directory)"
  fi
done

# 7. stderr that cannot be written never aborts a run.
"$bin" run spec.toml -o devfull.h5 2>/dev/full
rc=$?
((rc == 0)) && same "stderr on /dev/full" devfull.h5 reference.h5 && ok "stderr on /dev/full: exit 0, the right file" ||
  bad "stderr on /dev/full: exit 0, the right file" "a step of this case failed without its own message (see the logs in the work directory)"
((rc == 0)) || bad "stderr on /dev/full" "exit $rc"
"$bin" run spec.toml -o devfull_bad.h5 --set integrator.h=0 2>/dev/full
rc=$?
((rc == 2)) && ok "bad input with stderr on /dev/full: exit 2, no abort" || bad "bad input with stderr on /dev/full" "exit $rc"

# 8. An output that appears during a run is not replaced without --force.
"$bin" run spec.toml -o appear.h5 --quiet "${long[@]}" >appear.log 2>&1 &
run_a=$!
if wait_for_blocks appear.h5 1; then
  echo "someone else's file" >appear.h5
  wait "$run_a"
  rc=$?
  if status_and_message "output appeared during the run" 1 $rc appear.log "appeared" &&
     [[ $(cat appear.h5) == "someone else's file" && -d appear.h5.journal && ! -e appear.h5.partial ]]; then
    "$bin" run spec.toml -o appear.h5 --resume --quiet "${long[@]}" >appear2.log 2>&1
    status_and_message "resume while the stranger is there" 2 $? appear2.log "move it away" &&
      mv appear.h5 stranger.h5 && "$bin" run spec.toml -o appear.h5 --resume --quiet "${long[@]}" &&
      same "resume after moving the stranger away" appear.h5 long_reference.h5 &&
      ok "an output that appeared mid-run is kept (exit 1), then --resume finishes from the journal" ||
  bad "an output that appeared mid-run is kept (exit 1), then --resume finishes from the journal" "a step of this case failed without its own message (see the logs in the work directory)"
  fi
else
  wait "$run_a"; bad "output appeared during the run" "no block journaled within 60 s"
fi

# 9. A --force run over an existing output, killed, resumes by its own spec; another spec's
# --resume neither finishes it nor deletes its journal.
"$bin" run spec.toml -o forced.h5 --quiet --set scene.gamma=0.2
CONTACTSWEEP_TEST_KILL=block:3 "$bin" run spec.toml -o forced.h5 --force --quiet 2>/dev/null
"$bin" run spec.toml -o forced.h5 --resume --set scene.gamma=0.2 >forced_other.log 2>&1
rc=$?
if ((rc == 0)) && grep -q "already complete" forced_other.log && (($(blocks_in forced.h5) >= 3)); then
  ok "--resume with the old output's spec: complete, and the forced run's journal is kept"
else
  bad "another spec's --resume" "exit $rc, $(blocks_in forced.h5) blocks left: $(cat forced_other.log)"
fi
"$bin" run spec.toml -o forced.h5 --resume --quiet && same "resume of a forced run" forced.h5 reference.h5 &&
  ok "a killed --force run resumes by its own spec and replaces the old output" ||
  bad "a killed --force run resumes by its own spec and replaces the old output" "a step of this case failed without its own message (see the logs in the work directory)"

# ...and a killed --force run over an output of the same spec (say, made by an older build) is
# finished from its journal, never taken as complete from the old file.
cp reference.h5 same.h5
CONTACTSWEEP_TEST_KILL=block:3 "$bin" run spec.toml -o same.h5 --force --quiet 2>/dev/null
"$bin" run spec.toml -o same.h5 --resume >same.log 2>&1
rc=$?
if ((rc == 0)) && grep -q "points loaded from the journal" same.log && same "forced run, same spec" same.h5 reference.h5; then
  ok "a killed --force run over the same spec's output resumes from its journal, not 'complete'"
elif ((rc != 0)) || ! grep -q "points loaded from the journal" same.log; then
  bad "forced run, same spec" "exit $rc: $(cat same.log)"
fi

# 11. A kill between the journal's creation and its manifest: --resume starts afresh.
mkdir -p early.h5.journal && : >early.h5.journal/lock && : >early.h5.journal/manifest.tmp
"$bin" run spec.toml -o early.h5 --resume --quiet && same "journal without a manifest" early.h5 reference.h5 &&
  ok "a journal holding no block (killed before its manifest): --resume starts afresh" ||
  bad "a journal holding no block (killed before its manifest): --resume starts afresh" "a step of this case failed without its own message (see the logs in the work directory)"
mkdir -p damaged.h5.journal && echo "contactsweep journal 2" >damaged.h5.journal/manifest
"$bin" run spec.toml -o damaged.h5 --resume --quiet && same "damaged manifest, no block" damaged.h5 reference.h5 &&
  ok "a damaged manifest with no block: --resume starts afresh" ||
  bad "a damaged manifest with no block: --resume starts afresh" "a step of this case failed without its own message (see the logs in the work directory)"

# A kill while a finished run removed its journal leaves debris (no manifest, no block) beside a
# complete output: --resume reports it complete and clears the debris.
cp reference.h5 debris.h5 && mkdir -p debris.h5.journal && : >debris.h5.journal/lock
"$bin" run spec.toml -o debris.h5 --resume >debris.log 2>&1
rc=$?
if ((rc == 0)) && grep -q "already complete" debris.log && [[ ! -e debris.h5.journal ]]; then
  ok "journal debris beside a complete output: --resume says complete and removes it"
else
  bad "journal debris" "exit $rc, journal $(ls -d debris.h5.journal 2>/dev/null): $(cat debris.log)"
fi

# 13. Smaller: -o '', a directory, a device, and the resume summary.
"$bin" run spec.toml -o '' >empty.log 2>&1
status_and_message "-o ''" 2 $? empty.log "output path is empty" && ok "-o '' is refused (exit 2)" ||
  bad "-o '' is refused (exit 2)" "a step of this case failed without its own message (see the logs in the work directory)"
mkdir -p adir.h5
"$bin" run spec.toml -o adir.h5 >dir.log 2>&1
status_and_message "output is a directory" 2 $? dir.log "is a directory" && ok "an output that is a directory: exit 2, named" ||
  bad "an output that is a directory: exit 2, named" "a step of this case failed without its own message (see the logs in the work directory)"
"$bin" run spec.toml -o /dev/null --force >dev.log 2>&1
status_and_message "--force over a device" 2 $? dev.log "not a regular file" && [[ -c /dev/null ]] &&
  ok "--force over a device node: refused (exit 2), the device kept" ||
  bad "--force over a device node: refused (exit 2), the device kept" "a step of this case failed without its own message (see the logs in the work directory)"
# The summary's counts: the points of the blocks in the journal (each block_size points, the
# last one fewer) loaded, the rest of the 131 × 127 integrated.
CONTACTSWEEP_TEST_KILL=block:5 "$bin" run spec.toml -o summary.h5 2>/dev/null
block_size=$(sed -n 's/^block_size //p' summary.h5.journal/manifest)
journaled=0
for f in summary.h5.journal/block_*.bin; do
  begin=${f##*block_} begin=${begin%.bin}
  journaled=$((journaled + (begin + block_size <= 16637 ? block_size : 16637 - begin)))
done
"$bin" run spec.toml -o summary.h5 --resume >summary.log 2>&1
rc=$?
counts=$(sed -n 's/.*; \([0-9]*\) points loaded from the journal, \([0-9]*\) integrated.*/\1 \2/p' summary.log)
if ((rc == 0 && $(blocks_in summary.h5) == 0)) && [[ -n $block_size && $counts == "$journaled $((16637 - journaled))" ]] &&
   ((journaled == 5 * block_size)); then
  ok "the resume summary counts the journal's $journaled points as loaded, the other $((16637 - journaled)) as integrated"
else
  bad "resume summary" "exit $rc, journal had $journaled points (block size ${block_size:-?}), summary says '$counts': $(cat summary.log)"
fi

echo "$passed passed, $failed failed, $skipped skipped"
((failed == 0)) || exit 1
((skipped == 0)) || exit 77
