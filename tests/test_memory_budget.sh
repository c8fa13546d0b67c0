#!/usr/bin/env bash
# The memory check counts blocks in flight, not the grid (issue 27): rank 0 writes blocks into
# the output as they finish, so a basin map with trajectories whose whole results exceed the
# budget runs, and writes the file a run without a budget writes; a budget below its blocks in
# flight is still refused (exit 2, nothing written). One thread: in flight = 2·threads + 4 blocks.
#
# test_memory_budget.sh BIN SPEC COMPARE WORK
set -u
bin=$1 spec=$2 compare=$3 work=$4
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
export OMP_NUM_THREADS=1
# 64² points; t_end 10 at h 0.01 with a sample every 100 steps: 11 samples of 5 trajectories,
# so 4 + 5·11 = 59 values a point; blocks of 256 points (the smallest), 16 of them.
args=(--set grid.q_0.n=64 --set grid.p_0.n=64 --set integrator.t_end=10
      --set "measures.trajectory={every=100}")
points=4096 values=59 limit=$((1536 * 1024))
fail() { echo "FAIL: $*"; exit 1; }
# Held to the end, the results alone would take more than the 80 % of the budget a run may use.
((points * values * 8 * 10 > 8 * limit)) || fail "the case no longer exceeds the budget as a whole"
"$bin" run "$spec" "${args[@]}" -o reference.h5 --quiet || fail "the run without a budget"
CONTACTSWEEP_MEMORY_LIMIT=1536K "$bin" run "$spec" "${args[@]}" -o budget.h5 --quiet >budget.log 2>&1 ||
  fail "refused under a budget its blocks in flight fit: $(cat budget.log)"
out=$(/usr/bin/python3 "$compare" reference.h5 budget.h5) || fail "budget.h5: $out"
CONTACTSWEEP_MEMORY_LIMIT=256K "$bin" run "$spec" "${args[@]}" -o small.h5 --quiet >small.log 2>&1
rc=$?
((rc == 2)) || fail "a budget below the blocks in flight: exit $rc, expected 2"
grep -q "blocks of 256 points in flight" small.log || fail "the message: $(cat small.log)"
[[ ! -e small.h5 && ! -e small.h5.partial && ! -e small.h5.journal ]] || fail "something was written"
# A basin map keeps its provisional labels to the end, compact (1 to 4 bytes a point, counted at
# 4), and rank 0 reads the labels back from the file a band of rows at a time for the
# statistics: 2048² points need ~51 MB here, where labels held as doubles plus the whole map's
# labels and the Wada test's plane on rank 0 needed ~140 MB (refused under this budget).
basin=(--set grid.q_0.n=2048 --set grid.p_0.n=2048 --set integrator.t_end=1)
CONTACTSWEEP_MEMORY_LIMIT=80M "$bin" run "$spec" "${basin[@]}" -o basin.h5 --quiet >basin.log 2>&1 ||
  fail "a basin map refused though its compact labels and one band fit: $(cat basin.log)"
CONTACTSWEEP_MEMORY_LIMIT=48M "$bin" run "$spec" "${basin[@]}" -o basin_small.h5 --quiet >basin_small.log 2>&1
rc=$?
((rc == 2)) || fail "a basin map whose compact labels do not fit: exit $rc, expected 2"
grep -q "memory" basin_small.log || fail "the refusal does not name memory: $(cat basin_small.log)"
[[ ! -e basin_small.h5 && ! -e basin_small.h5.partial && ! -e basin_small.h5.journal ]] ||
  fail "a refused basin map wrote something"
# The recurrence mapper's record and reason (88 bytes a point) are counted per point to the end:
# a saved block keeps them per distinct entry only where that costs less
# (engine/recurrence/lane_records.hpp), so per point is the most it holds. Its 1024² map is
# counted at 0.115 GiB here: it fits 160 MiB and is refused at 128 MiB, where counting entries at
# an average (7 values a point rather than 11) would let it run.
recurrence=(--set grid.q_0.n=1024 --set grid.p_0.n=1024 --set integrator.t_end=1
            --set measures.basin.recurrence=true)
CONTACTSWEEP_MEMORY_LIMIT=160M "$bin" run "$spec" "${recurrence[@]}" -o recurrence.h5 --quiet >recurrence.log 2>&1 ||
  fail "a recurrence map refused though its records in flight fit: $(cat recurrence.log)"
CONTACTSWEEP_MEMORY_LIMIT=128M "$bin" run "$spec" "${recurrence[@]}" -o recurrence_small.h5 --quiet >recurrence_small.log 2>&1
rc=$?
((rc == 2)) && grep -q "memory" recurrence_small.log ||
  fail "a recurrence map whose labels and blocks in flight do not fit: exit $rc, $(cat recurrence_small.log)"
echo "ok: counted blocks in flight (accepted at 1.5 MiB, refused at 256 KiB); a 2048² basin map passes the check at 80 MiB, refused at 48 MiB; a 1024² recurrence map at 160 MiB, refused at 128 MiB"
