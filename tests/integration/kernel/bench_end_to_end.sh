#!/bin/sh
# hrg-bench driving hrg-table-sim (Modbus TCP on 127.0.0.1) and hrg-gyro-sim (SocketCAN on vcan0)
# as separate processes, inside the QEMU guest (busybox sh). Usage:
#   bench_end_to_end.sh BIN_DIR CONFIG_DIR
# Passes when the session is PASS (no limits: the estimate is usable), with 3 complete runs in
# session.json, the CAN log stamped in Unix time, the estimate within 5 std of the truth, and the
# raw CAN log rebuilding every run and the estimate bit for bit: through the gyro driver
# (hrg-bench replay), and again after can-utils' canplayer has put it back on vcan0 in real time
# and candump has recorded that traffic (CANUTILS_DIR: where canplayer and candump are).
bin="$1"
cfg="$2"
canutils="${3:-/usr/bin}"
out=/tmp/bench-e2e
"$bin/hrg-table-sim" --tcp 127.0.0.1:1502 --noise 1e-6 &
table=$!
"$bin/hrg-gyro-sim" --can vcan0 --config "$cfg/gyro_sim_e2e.toml" --table 127.0.0.1:1502 &
gyro=$!
sleep 1
status=0
"$bin/hrg-bench" run --station "$cfg/bench_vm_station.toml" --sequence "$cfg/bench_vm_sequence.toml" \
  --serial VM-0001 -o "$out" > /tmp/bench-e2e.out 2>&1 || status=$?
cat /tmp/bench-e2e.out
kill "$gyro" "$table" 2>/dev/null || true
echo "hrg-bench exit $status"
ls "$out/runs"
fail=0
check() {  # check WHAT CONDITION-EXIT-CODE
  if [ "$2" -eq 0 ]; then echo "ok: $1"; else echo "FAIL: $1"; fail=1; fi
}
[ "$status" -eq 0 ]; check "hrg-bench exits 0 (PASS)" $?
grep -q '"kind": "PASS"' "$out/session.json"; check "session.json outcome PASS" $?
# A run's own status (session.json is indented by 2: runs[k].status is at 6 spaces; its end's
# status, also "complete", at 8).
complete=$(grep -c '^      "status": "complete"' "$out/session.json" || true)
[ "$complete" -eq 3 ]; check "3 complete runs in session.json (found $complete)" $?
[ -f "$out/runs/run-003.csv" ]; check "run-003.csv on disk" $?
lines=$(wc -l < "$out/can/session.log")
[ "$lines" -gt 1000 ]; check "CAN log holds the session's frames ($lines lines)" $?
# The candump log's stamps are Unix time (SocketCAN software stamps are CLOCK_REALTIME): the first
# frame was logged within the last hour of the guest's own clock.
first=$(head -n 1 "$out/can/session.log" | sed 's/^(\([0-9]*\)\..*/\1/')
age=$(( $(date +%s) - first ))
[ "$age" -ge 0 ] && [ "$age" -lt 3600 ]; check "first CAN log stamp $first is $age s old" $?
# The estimate agrees with hrg-gyro-sim's truth (gyro_sim_e2e.toml: delta, xi = 0) within 5 of
# its reported standard deviations.
awk -v truth="-0.05 0.3 2e-3 -1e-3 3e-3 1e-3" -f "$cfg/estimate_within_5_std.awk" /tmp/bench-e2e.out
check "estimate within 5 std of the truth" $?

# The raw CAN log, recorded on a real kernel interface across processes, rebuilds the record.
"$bin/hrg-bench" replay "$out" > /tmp/replay.out 2>&1
replayed=$?
cat /tmp/replay.out
[ "$replayed" -eq 0 ]; check "hrg-bench replay: the CAN log rebuilds every run and the estimate" $?
# can-utils puts the same log back on vcan0 (canplayer keeps its timing) while candump records
# the bus; that recording, in place of the session's log, rebuilds them too.
played=/tmp/bench-e2e-played
cp -r "$out" "$played"
"$canutils/candump" -L vcan0 > "$played/can/session.log" &
dump=$!
sleep 1
"$canutils/canplayer" -I "$out/can/session.log"
player=$?
sleep 1
kill "$dump"
wait "$dump" 2>/dev/null
[ "$player" -eq 0 ]; check "canplayer played the session's log on vcan0" $?
sent=$(wc -l < "$out/can/session.log")
seen=$(wc -l < "$played/can/session.log")
[ "$seen" -eq "$sent" ]; check "candump saw every frame canplayer sent ($seen of $sent)" $?
"$bin/hrg-bench" replay "$played" > /tmp/replay-played.out 2>&1
replayed=$?
cat /tmp/replay-played.out
[ "$replayed" -eq 0 ]; check "the log as canplayer played it rebuilds every run and the estimate" $?
exit "$fail"
