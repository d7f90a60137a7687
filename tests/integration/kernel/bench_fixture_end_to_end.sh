#!/bin/sh
# A fixture of two units across processes in the QEMU guest (busybox sh): hrg-bench drives
# hrg-table-sim (Modbus TCP on 127.0.0.1) and two hrg-gyro-sim processes on one bus, vcan0, as
# nodes 1 and 2 (gyro CAN protocol v2), as one table with two units (bench_vm_fixture_station.toml).
# Usage:
#   bench_fixture_end_to_end.sh BIN_DIR CONFIG_DIR
# Passes when both units PASS (no limits: each estimate usable) with 3 complete runs each, each
# unit's estimate is within 5 of its std of its own simulator's truth (and not of the other's), and
# each unit's raw CAN log holds its own node's traffic only and rebuilds its record bit for bit
# (hrg-bench replay).
bin="$1"
cfg="$2"
out=/tmp/bench-fixture
"$bin/hrg-table-sim" --tcp 127.0.0.1:1502 --noise 1e-6 &
table=$!
"$bin/hrg-gyro-sim" --can vcan0 --node 1 --config "$cfg/gyro_sim_e2e.toml" \
  --table 127.0.0.1:1502 &
gyro_a=$!
"$bin/hrg-gyro-sim" --can vcan0 --node 2 --config "$cfg/gyro_sim_e2e_b.toml" \
  --table 127.0.0.1:1502 &
gyro_b=$!
sleep 1
status=0
"$bin/hrg-bench" run --station "$cfg/bench_vm_fixture_station.toml" \
  --sequence "$cfg/bench_vm_sequence.toml" --serial VM-A --serial VM-B -o "$out" \
  > /tmp/bench-fixture.out 2>&1 || status=$?
cat /tmp/bench-fixture.out
kill "$gyro_a" "$gyro_b" "$table" 2>/dev/null || true
echo "hrg-bench exit $status"
fail=0
check() {  # check WHAT CONDITION-EXIT-CODE
  if [ "$2" -eq 0 ]; then echo "ok: $1"; else echo "FAIL: $1"; fail=1; fi
}
[ "$status" -eq 0 ]; check "hrg-bench exits 0 (both units PASS)" $?
passes=$(grep -c '"kind": "PASS"' "$out/fixture.json" || true)
[ "$passes" -eq 2 ]; check "fixture.json: 2 units PASS (found $passes)" $?
# Each unit against its own simulator's truth (gyro_sim_e2e.toml as node 1, gyro_sim_e2e_b.toml as
# node 2; xi = 0), from hrg-estimate's table.
agrees() {  # agrees SESSION_DIR "TRUTH_DELTA1..6"
  "$bin/hrg-estimate" "$1" > "$1.estimate" 2>&1
  awk -v truth="$2" -f "$cfg/estimate_within_5_std.awk" "$1.estimate"
}
truth_a="-0.05 0.3 2e-3 -1e-3 3e-3 1e-3"
truth_b="-0.04 0.28 -1e-3 2e-3 -2e-3 4e-3"
for unit in A-VM-A B-VM-B; do
  complete=$(grep -c '^      "status": "complete"' "$out/$unit/session.json" || true)
  [ "$complete" -eq 3 ]; check "$unit: 3 complete runs (found $complete)" $?
  "$bin/hrg-bench" replay "$out/$unit" > "/tmp/replay-$unit.out" 2>&1
  replayed=$?
  cat "/tmp/replay-$unit.out"
  [ "$replayed" -eq 0 ]; check "$unit: its CAN log rebuilds every run and the estimate" $?
done
# Each log is its own node's: identifiers end in its node id (message | node), none in the other's.
own_b=$(grep -c ' vcan0 [0-9A-F][0-9A-F]2#' "$out/B-VM-B/can/session.log" || true)
other_b=$(grep -c ' vcan0 [0-9A-F][0-9A-F]1#' "$out/B-VM-B/can/session.log" || true)
[ "$own_b" -gt 1000 ] && [ "$other_b" -eq 0 ]
check "B's log: node 2's frames ($own_b), none of node 1's ($other_b)" $?
own_a=$(grep -c ' vcan0 [0-9A-F][0-9A-F]1#' "$out/A-VM-A/can/session.log" || true)
other_a=$(grep -c ' vcan0 [0-9A-F][0-9A-F]2#' "$out/A-VM-A/can/session.log" || true)
[ "$own_a" -gt 1000 ] && [ "$other_a" -eq 0 ]
check "A's log: node 1's frames ($own_a), none of node 2's ($other_a)" $?
agrees "$out/A-VM-A" "$truth_a"; check "A's estimate within 5 std of A's truth" $?
agrees "$out/B-VM-B" "$truth_b"; check "B's estimate within 5 std of B's truth" $?
agrees "$out/B-VM-B" "$truth_a" > /dev/null; [ $? -ne 0 ]; check "B's estimate is not A's truth" $?
exit "$fail"
