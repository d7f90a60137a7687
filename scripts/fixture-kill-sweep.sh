#!/usr/bin/env bash
# kill -9 of a fixture session at every STEP seconds of its first LIMIT seconds (wall clock, as an
# operator or a power cut would), then `hrg-bench resume` of what it left. Each folder is counted
# as: resumed (every unit's record closed, every run complete), not started (the kill came before
# fixture.json: resume refuses and says nothing was run), or UNRESUMABLE (anything else).
# The deterministic test of the same is bench_program_test's FixtureKilledAtAnyWritePointResumes;
# this is the measurement (docs/measurements/2026-11-26-fixture-kill-sweep.md).
#
#   scripts/fixture-kill-sweep.sh [BUILD_DIR] [STEP_S] [LIMIT_S] [START_S]
#   (defaults: build 0.01 1.0 0: kills at START+STEP, START+2 STEP, ... START+LIMIT; on a loaded
#   machine the program's start-up can take most of the first second: shift the window with START)
set -u
build=${1:-build}
step=${2:-0.01}
limit=${3:-1.0}
start=${4:-0}
bench="$build/bin/hrg-bench"
src=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d /tmp/hrgbench-kill-sweep-XXXXXX)
# The shipped four-unit station without its results store, and the paper's sequence cut to two
# 1 s runs with a 1 s warm-up window: a whole fixture takes seconds.
sed '/^\[results\]/,/^url/d' "$src/bench_configs/station-sim-fixture.toml" > "$work/station.toml"
python3 - "$src/bench_configs/sequence-paper.toml" "$work/sequence.toml" <<'PY'
import sys
s = open(sys.argv[1]).read().replace("window_s = 60.0", "window_s = 1.0")
s = s.replace("free_run_s = 10.0", "free_run_s = 1.0")
at = 0
for _ in range(3):
    at = s.find("[[runs]]", at + 1)
open(sys.argv[2], "w").write(s[:at])
PY
export HRGBENCH_CHROMIUM=/bin/false  # no PDF: seconds per fixture
resumed=0; not_started=0; unresumable=0; no_folder=0
for t in $(python3 -c "n=round($limit/$step); print(' '.join(f'{$start+(i+1)*$step:.3f}' for i in range(n)))"); do
  dir="$work/f$t"
  "$bench" run --station "$work/station.toml" --sequence "$work/sequence.toml" \
    --serial KS1 --serial KS2 --serial KS3 --serial KS4 -o "$dir" > "$work/run-$t.log" 2>&1 &
  pid=$!
  sleep "$t"
  kill -9 "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  if [ ! -d "$dir" ]; then no_folder=$((no_folder + 1)); echo "$t no folder"; continue; fi
  "$bench" resume "$dir" > "$work/resume-$t.log" 2>&1
  code=$?
  closed=$(python3 - "$dir" <<'PY'
import json, pathlib, sys
d = pathlib.Path(sys.argv[1])
ok = (d / "fixture.json").exists()
for u in (json.load(open(d / "fixture.json"))["units"] if ok else []):
    try:
        s = json.load(open(d / u["folder"] / "session.json"))
        ok = ok and s["state"] == "closed" and all(r["status"] == "complete" for r in s["runs"])
    except Exception:
        ok = False
print("yes" if ok else "no")
PY
)
  if [ "$closed" = yes ] && [ "$code" -le 2 ]; then
    resumed=$((resumed + 1)); echo "$t resumed (exit $code)"
  elif [ "$code" = 4 ] && grep -q "nothing was run" "$work/resume-$t.log"; then
    not_started=$((not_started + 1)); echo "$t not started (refused with the reason)"
  else
    unresumable=$((unresumable + 1)); echo "$t UNRESUMABLE (exit $code): $(tail -1 "$work/resume-$t.log")"
  fi
done
echo "kills: $(python3 -c "print(round($limit/$step))")  no folder: $no_folder  not started: $not_started  resumed: $resumed  UNRESUMABLE: $unresumable"
rm -rf "$work"
[ "$unresumable" = 0 ]
