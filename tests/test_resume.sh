#!/usr/bin/env bash
# Kill real runs at several points (kill -9 between blocks, after the datasets are written into
# the temporary file but before it is committed, right after the commit, and at moments spread
# over a run's duration), continue each with --resume — sometimes with
# another rank count — and require the result to equal an uninterrupted run in every dataset.
# Usage: test_resume.sh CONTACTSWEEP SPEC COMPARE_SCRIPT WORKDIR [LONG_T_END=400] [GRID=211x190]
# LONG_T_END sets the length of the runs killed at timed moments (~2.5 s on 2 ranks in a release
# build at 1500, well beyond mpirun's ~0.5 s start-up; the sanitizer build, ~60x slower in this
# kernel, passes 160 with a grid of a quarter the points). GRID is q_0's n x p_0's: the sanitizer
# build passes 105x95, still 39 blocks (of at least 256 points), so that every kill point (the
# 8th block, 3 of them saved before a signal) lies inside the run.
set -uo pipefail
bin=$1 spec=$2 compare=$3 work=$4 long_t_end=${5:-400} grid=${6:-211x190}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
mpirun=(mpirun --oversubscribe --bind-to none)
args=(--quiet --set "grid.q_0.n=${grid%x*}" --set "grid.p_0.n=${grid#*x}" --set integrator.t_end=40
      --set measures.final_state=true)
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failures=0 trials=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

"$bin" run "$spec" -o reference.h5 "${args[@]}" || { echo "reference run failed"; exit 1; }

check() {  # check NAME: NAME.h5 complete, journal gone, identical to the reference
  trials=$((trials + 1))
  [[ -f $1.h5 && ! -e $1.h5.journal && ! -e $1.h5.partial ]] || { fail "$1: leftovers: $(ls -d "$1".h5* 2>/dev/null)"; return; }
  python_out=$(/usr/bin/python3 "$compare" reference.h5 "$1.h5") || fail "$1: $python_out"
}

# Deterministic kill points (the test hook CONTACTSWEEP_TEST_KILL), resumed on 1 or 2 ranks.
for point in block:1 block:7 write commit; do
  for resume_ranks in 1 2; do
    name="kill_${point/:/_}_np$resume_ranks"
    CONTACTSWEEP_TEST_KILL=$point "$bin" run "$spec" -o "$name.h5" "${args[@]}" 2>/dev/null
    status=$?
    [[ $status -eq 137 ]] || fail "$name: expected death by SIGKILL (137), got $status"
    [[ ! -e $name.h5 || $point == commit ]] || fail "$name: an output appeared before the commit"
    "${mpirun[@]}" -np "$resume_ranks" "$bin" run "$spec" -o "$name.h5" --resume "${args[@]}" \
      || fail "$name: resume exited $?"
    check "$name"
  done
done

# One rank of two dies (the other is still computing): the job must end with a non-zero
# status and leave a journal that --resume (on one rank) finishes.
name=rank_dies
CONTACTSWEEP_TEST_KILL=block:2@1 "${mpirun[@]}" -np 2 "$bin" run "$spec" -o "$name.h5" "${args[@]}" \
  > "$name.log" 2>&1
status=$?
[[ $status -ne 0 ]] || fail "$name: mpirun exited 0 although rank 1 died"
[[ ! -e $name.h5 && -d $name.h5.journal ]] || fail "$name: expected a journal and no output"
"$bin" run "$spec" -o "$name.h5" --resume "${args[@]}" || fail "$name: resume exited $?"
check "$name"

# SIGTERM (a batch system's time limit) or SIGINT after the 3rd saved block (the test hook sends
# it to the process, as from outside): no block is started after it, those being computed are
# saved, the temporary file is removed and the journal kept; the exit status is 128 + the signal
# with a message naming it; --resume (on 1 or 2 ranks) finishes the file.
stopped_message() {  # stopped_message NAME SIGNAL LOG: the message, with at least 3 blocks saved
  local line saved total
  line=$(grep "^contactsweep: stopped by $2; [0-9]* of [0-9]* blocks saved in $1.h5.journal; run again with --resume to continue$" "$3") ||
    { fail "$1: no stop message in: $(cat "$3")"; return; }
  read -r saved total < <(sed 's/.*; \([0-9]*\) of \([0-9]*\) blocks.*/\1 \2/' <<<"$line")
  ((saved >= 3 && saved < total)) || fail "$1: $saved of $total blocks saved, expected 3 to $((total - 1))"
  echo "$1: $line"
}
for sig in TERM:143:1 INT:130:2; do
  IFS=: read -r signal expected resume_ranks <<<"$sig"
  name="signal_$signal"
  CONTACTSWEEP_TEST_KILL="block:3/${signal,,}" "$bin" run "$spec" -o "$name.h5" "${args[@]}" \
    2> "$name.log"
  status=$?
  [[ $status -eq $expected ]] || fail "$name: expected exit status $expected, got $status"
  [[ ! -e $name.h5 && ! -e $name.h5.partial && -d $name.h5.journal ]] ||
    fail "$name: expected the journal alone, found: $(ls -d "$name".h5* 2>/dev/null)"
  stopped_message "$name" "SIG$signal" "$name.log"
  "${mpirun[@]}" -np "$resume_ranks" "$bin" run "$spec" -o "$name.h5" --resume "${args[@]}" \
    || fail "$name: resume exited $?"
  check "$name"
done
# A SIGTERM while the file is being completed is ignored: the run completes it (exit 0).
name=signal_at_write
CONTACTSWEEP_TEST_KILL=write/term "$bin" run "$spec" -o "$name.h5" "${args[@]}" \
  || fail "$name: exited $?"
check "$name"

# Kill a 2-rank run with kill -9 to its whole job at moments spread over its duration (measured
# here, so the kills land inside the run on a fast machine and under the sanitizers alike), then
# resume. These runs integrate every lane to LONG_T_END (no early stop) so that they last.
long_args=("${args[@]}" --set "integrator.t_end=$long_t_end" --set measures.basin.early_stop=false)
start=$(date +%s.%N)
"${mpirun[@]}" -np 2 "$bin" run "$spec" -o long_reference.h5 "${long_args[@]}" \
  || { echo "long reference run failed"; exit 1; }
duration=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print b - a}')
echo "uninterrupted 2-rank run: $duration s"
interrupted=0
for fraction in 0.15 0.35 0.55 0.75 0.9; do
  name="timed_$fraction"
  delay=$(awk -v d="$duration" -v f="$fraction" 'BEGIN {print d * f}')
  "${mpirun[@]}" -np 2 "$bin" run "$spec" -o "$name.h5" "${long_args[@]}" 2>/dev/null &
  job=$!
  sleep "$delay"
  pkill -9 -f -- "-o $name.h5" ; wait "$job" 2>/dev/null
  # Finished blocks only: the journal also holds its lock and manifest from the start.
  journaled=$(find "$name.h5.journal" -maxdepth 1 -name 'block_*.bin' 2>/dev/null | wc -l)
  if [[ ! -e $name.h5 ]]; then
    ((journaled > 0)) && interrupted=$((interrupted + 1))
    echo "$name: killed at $delay s, before the commit ($journaled blocks journaled)"
  else
    echo "$name: killed at $delay s, after the commit"
  fi
  # A second kill during the resume, then the final resume.
  "$bin" run "$spec" -o "$name.h5" --resume "${long_args[@]}" & job=$!
  sleep 0.1; kill -9 "$job" 2>/dev/null; wait "$job" 2>/dev/null
  "$bin" run "$spec" -o "$name.h5" --resume "${long_args[@]}" || fail "$name: resume exited $?"
  trials=$((trials + 1))
  [[ -f $name.h5 && ! -e $name.h5.journal ]] || fail "$name: leftovers: $(ls -d "$name".h5* 2>/dev/null)"
  python_out=$(/usr/bin/python3 "$compare" long_reference.h5 "$name.h5") || fail "$name: $python_out"
done
# MPI start-up takes a share of the measured duration, so the earliest kill may land before any
# block is done and the last after the commit; at least two must land mid-run, with finished
# blocks journaled and no output yet, or this part tested nothing.
((interrupted >= 2)) || fail "only $interrupted of 5 timed kills landed mid-run"

# SIGTERM to both ranks of a 2-rank run from outside, as Slurm signals every task at the time
# limit, once 3 blocks are journaled: both stop, the job exits 143, the journal alone is left,
# and --resume on one rank finishes the file.
name=signal_np2
"${mpirun[@]}" -np 2 "$bin" run "$spec" -o "$name.h5" "${long_args[@]}" 2> "$name.log" &
job=$!
for ((i = 0; i < 600; ++i)); do  # up to 30 s
  (($(find "$name.h5.journal" -maxdepth 1 -name 'block_*.bin' 2>/dev/null | wc -l) >= 3)) && break
  sleep 0.05
done
ranks=$(pgrep -P "$job")  # mpirun's children: the ranks
kill -TERM $ranks
wait "$job"
status=$?
[[ $status -eq 143 ]] || fail "$name: expected exit status 143, got $status (ranks: $ranks)"
[[ ! -e $name.h5 && ! -e $name.h5.partial && -d $name.h5.journal ]] ||
  fail "$name: expected the journal alone, found: $(ls -d "$name".h5* 2>/dev/null)"
stopped_message "$name" SIGTERM "$name.log"
"$bin" run "$spec" -o "$name.h5" --resume "${long_args[@]}" || fail "$name: resume exited $?"
trials=$((trials + 1))
[[ -f $name.h5 && ! -e $name.h5.journal && ! -e $name.h5.partial ]] ||
  fail "$name: leftovers: $(ls -d "$name".h5* 2>/dev/null)"
python_out=$(/usr/bin/python3 "$compare" long_reference.h5 "$name.h5") || fail "$name: $python_out"

# --resume of a finished output is a no-op (the file keeps its bytes and its mtime, no journal is
# left); of another spec's output, a refusal (exit 2).
before=$(stat -c '%y %s' reference.h5; sha256sum <reference.h5)
"$bin" run "$spec" -o reference.h5 --resume "${args[@]}" || fail "resume of a complete run exited $?"
after=$(stat -c '%y %s' reference.h5; sha256sum <reference.h5)
[[ $after == "$before" && ! -e reference.h5.journal ]] ||
  fail "resume of a complete run touched it: $before -> $after$(ls -d reference.h5.journal 2>/dev/null)"
"$bin" run "$spec" -o reference.h5 --resume --quiet --set integrator.t_end=20 2>/dev/null
[[ $? -eq 2 ]] || fail "resume with another spec was not refused with status 2"

echo "resume trials: $trials"
echo "$((trials - failures)) passed, $failures failed"
[[ $failures -eq 0 ]]
