#!/usr/bin/env bash
# Kill real runs at several points (kill -9 between blocks, after the datasets are written into
# the temporary file but before it is committed, right after the commit, and at moments spread
# over a run's duration), continue each with --resume — sometimes with
# another rank count — and require the result to equal an uninterrupted run in every dataset.
# Usage: test_resume.sh CONTACTSWEEP SPEC COMPARE_SCRIPT WORKDIR [LONG_T_END=400]
# LONG_T_END sets the length of the runs killed at timed moments (~2.5 s on 2 ranks in a release
# build at 1500, well beyond mpirun's ~0.5 s start-up; the sanitizer build, ~60x slower in this
# kernel, passes 40).
set -uo pipefail
bin=$1 spec=$2 compare=$3 work=$4 long_t_end=${5:-400}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
mpirun=(mpirun --oversubscribe --bind-to none)
args=(--quiet --set grid.q_0.n=211 --set grid.p_0.n=190 --set integrator.t_end=40
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
