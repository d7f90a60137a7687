#!/usr/bin/env bash
# README command 2: install what is missing (Debian packages), build, run every test:
#   1. every ctest test on the host (unit and loopback integration tests), then
#   2. the tests that need a real Linux CAN stack, inside Debian's own kernel under QEMU
#      (label "kernel"; this machine's kernel has no AF_CAN/vcan), then
#   3. the readers of every input, built with AddressSanitizer and UndefinedBehaviorSanitizer
#      (scripts/run-sanitized-tests.sh --fast, in build-sanitize/; once, whatever the repeat).
# Nothing is skipped: the run is strict (HRGBENCH_STRICT=1), so a test whose tool is missing fails,
# and a part that has no tests to run fails. It says what it runs and how many passed.
#
# The load check of docs/testing.md (the suite green with both cores busy beside it):
#   HRGBENCH_TEST_REPEAT=5 HRGBENCH_TEST_LOAD=1 bash scripts/run-tests.sh
# HRGBENCH_TEST_REPEAT=N runs both parts N times (stopping at the first failure);
# HRGBENCH_TEST_LOAD=1 runs `stress-ng --cpu <cores>` beside the tests for the whole time.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
repeat="${HRGBENCH_TEST_REPEAT:-1}"
export HRGBENCH_STRICT=1

bash "$root/scripts/setup-debian.sh"
bash "$root/scripts/build.sh"
bash "$root/scripts/setup-kernel-tests.sh" "$build"

# Counts the tests a label selection holds, without a pipe that can die of SIGPIPE (grep -q exits
# at its first match; ctest then dies and, under pipefail, the test was read as "no tests").
count_tests() {
  local listing
  listing="$(ctest --test-dir "$build" -N "$@")"
  grep -c 'Test *#' <<<"$listing" || true
}
host_selection=(-LE 'kernel|vm_guest')  # vm_guest: binaries that only make sense inside the VM
kernel_selection=(-L '^kernel$')
host_count="$(count_tests "${host_selection[@]}")"
kernel_count="$(count_tests "${kernel_selection[@]}")"
if [ "$host_count" -eq 0 ] || [ "$kernel_count" -eq 0 ]; then
  echo "run-tests: FAIL: found $host_count host and $kernel_count kernel tests; both parts must run" >&2
  exit 1
fi

# The tests' scratch space is a folder of this run's own (TMPDIR), removed at the end: what a test
# leaves behind is said, not piled up in /tmp run after run (sessions are ~120 MB each).
test_tmp="$(mktemp -d "${TMPDIR:-/tmp}/hrgbench-tests.XXXXXX")"
# As /tmp is: the PostgreSQL tests run initdb and the server as the user postgres, in here.
chmod 1777 "$test_tmp"
export TMPDIR="$test_tmp"
disk_free() { df -h --output=avail "$1" | tail -n 1 | tr -d ' '; }
echo "run-tests: scratch $test_tmp; free: $(disk_free "$build") beside the build, $(disk_free "$test_tmp") for scratch"

load_pid=""
finish() {
  [ -z "$load_pid" ] || kill "$load_pid" 2>/dev/null || true
  local left
  left="$(find "$test_tmp" -mindepth 1 -maxdepth 1 | wc -l)"
  if [ "$left" -ne 0 ]; then
    echo "run-tests: the tests left $left entries ($(du -sh "$test_tmp" | cut -f1)) in their scratch; removed:"
    find "$test_tmp" -mindepth 1 -maxdepth 1 -printf '  %f\n' | sort | head -n 20
  fi
  rm -rf "$test_tmp"
}
trap finish EXIT
if [ "${HRGBENCH_TEST_LOAD:-0}" = "1" ]; then
  command -v stress-ng >/dev/null || { echo "run-tests: stress-ng missing" >&2; exit 1; }
  stress-ng --cpu "$(nproc)" --timeout 0 --quiet &
  load_pid=$!
  echo "run-tests: stress-ng --cpu $(nproc) running beside the tests (pid $load_pid)"
fi

# --timeout: a backstop for a test registered without its own (every test has one).
for ((pass = 1; pass <= repeat; ++pass)); do
  [ "$repeat" -eq 1 ] || echo "run-tests: pass $pass of $repeat"
  status=0
  echo "run-tests: part 1 of 3: $host_count host tests (unit, loopback integration)"
  ctest --test-dir "$build" --output-on-failure -j "$(nproc)" --timeout 900 \
    "${host_selection[@]}" || status=$?
  echo "run-tests: part 2 of 3: $kernel_count kernel tests (Debian's kernel under QEMU)"
  ctest --test-dir "$build" --output-on-failure --timeout 900 "${kernel_selection[@]}" || status=$?
  if [ "$status" -ne 0 ]; then
    echo "run-tests: FAIL in pass $pass of $repeat" >&2
    exit "$status"
  fi
done
echo "run-tests: free: $(disk_free "$build") beside the build"
echo "run-tests: part 3 of 3: the input readers, sanitized (AddressSanitizer, UndefinedBehaviorSanitizer)"
bash "$root/scripts/run-sanitized-tests.sh" --fast
echo "run-tests: every test passed ($host_count host, $kernel_count kernel$([ "$repeat" -eq 1 ] || echo ", $repeat passes"), the sanitized readers)"
