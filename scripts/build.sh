#!/usr/bin/env bash
# Configures and builds hrgbench in BUILD_DIR (default: build/), warnings as errors.
# Extra arguments go to the CMake configure step (e.g. -DCMAKE_BUILD_TYPE=Debug).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -G Ninja -DHRGBENCH_WERROR=ON "$@"
cmake --build "$build" -j "$(nproc)"
