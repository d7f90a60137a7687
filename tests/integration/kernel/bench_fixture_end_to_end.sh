#!/bin/sh
# A fixture of two units across processes in the QEMU guest (busybox sh): hrg-bench drives
# hrg-table-sim (Modbus TCP on 127.0.0.1) and two hrg-gyro-sim processes, one on vcan0 and one on
# vcan1, as one table with two units (bench_vm_fixture_station.toml). Usage:
#   bench_fixture_end_to_end.sh BIN_DIR CONFIG_DIR
# Passes when both units PASS (no limits: each estimate usable) with 3 complete runs each, each
# unit's estimate is within 5 of its std of its own simulator's truth (and not of the other's), and
# each unit's raw CAN log rebuilds its record bit for bit (hrg-bench replay).
bin="$1"
cfg="$2"
out=/tmp/bench-fixture
ip link add dev vcan1 type vcan && ip link set vcan1 mtu 72 up || { echo "FAIL: vcan1"; exit 1; }
"$bin/hrg-table-sim" --tcp 127.0.0.1:1502 --noise 1e-6 &
table=$!
"$bin/hrg-gyro-sim" --can vcan0 --config "$cfg/gyro_sim_e2e.toml" --table 127.0.0.1:1502 &
gyro_a=$!
"$bin/hrg-gyro-sim" --can vcan1 --config "$cfg/gyro_sim_e2e_b.toml" --table 127.0.0.1:1502 &
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
# Each unit against its own simulator's truth (gyro_sim_e2e.toml on vcan0, gyro_sim_e2e_b.toml on
# vcan1; xi = 0), from hrg-estimate's table.
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
grep -q ' vcan1 ' "$out/B-VM-B/can/session.log"; check "B's log is vcan1's" $?
agrees "$out/A-VM-A" "$truth_a"; check "A's estimate within 5 std of A's truth" $?
agrees "$out/B-VM-B" "$truth_b"; check "B's estimate within 5 std of B's truth" $?
agrees "$out/B-VM-B" "$truth_a" > /dev/null; [ $? -ne 0 ]; check "B's estimate is not A's truth" $?
exit "$fail"
