#!/bin/sh
# hrg-bench driving hrg-table-sim (Modbus TCP on 127.0.0.1) and hrg-gyro-sim (SocketCAN on vcan0)
# as separate processes, inside the QEMU guest (busybox sh). Usage:
#   bench_end_to_end.sh BIN_DIR CONFIG_DIR
# Passes when the session is PASS (no limits: the estimate is usable), with 3 complete runs.
set -e
bin="$1"
cfg="$2"
out=/tmp/bench-e2e
"$bin/hrg-table-sim" --tcp 127.0.0.1:1502 --noise 1e-6 &
table=$!
"$bin/hrg-gyro-sim" --can vcan0 --config "$cfg/gyro_sim_e2e.toml" --table 127.0.0.1:1502 &
gyro=$!
sleep 1
status=0
"$bin/hrg-bench" run --station "$cfg/bench_vm_station.toml" --sequence "$cfg/bench_vm_sequence.toml" \
  --serial VM-0001 -o "$out" || status=$?
kill "$gyro" "$table" 2>/dev/null || true
echo "hrg-bench exit $status"
ls "$out/runs"
complete=$(grep -c '"status": "complete"' "$out/session.json" || true)
echo "complete run entries in session.json: $complete"
lines=$(wc -l < "$out/can/session.log")
echo "CAN log lines: $lines"
# The candump log's stamps are Unix time (SocketCAN software stamps are CLOCK_REALTIME): the first
# frame was logged within the last hour of the guest's own clock.
first=$(head -n 1 "$out/can/session.log" | sed 's/^(\([0-9]*\)\..*/\1/')
age=$(( $(date +%s) - first ))
echo "first CAN log stamp $first, $age s ago"
[ "$status" -eq 0 ] && [ -f "$out/runs/run-003.csv" ] && [ "$lines" -gt 1000 ] &&
  [ "$age" -ge 0 ] && [ "$age" -lt 3600 ]
