#!/usr/bin/env bash
# README command 2: install what is missing (Debian packages), build, run every test:
#   1. every ctest test on the host (unit and loopback integration tests), then
#   2. the tests that need a real Linux CAN stack, inside Debian's own kernel under QEMU
#      (label "kernel"; this machine's kernel has no AF_CAN/vcan).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
bash "$root/scripts/setup-debian.sh"
bash "$root/scripts/build.sh"
status=0
# vm_guest: test binaries that only make sense inside the kernel VM (they would skip here).
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" -LE 'kernel|vm_guest' || status=$?
if [ -f "$root/scripts/setup-kernel-tests.sh" ] && ctest --test-dir "$build" -N -L '^kernel$' | grep -q 'Test #'; then
  bash "$root/scripts/setup-kernel-tests.sh" "$build"
  ctest --test-dir "$build" --output-on-failure -L '^kernel$' || status=$?
fi
exit "$status"
