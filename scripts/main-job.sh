#!/usr/bin/env bash
# The main job: simulate the paper's experiment (bench_configs/sim-paper.toml) into
# build/out/sim-paper and compare the paper's method, the paper's xi1 grid and maximum likelihood on
# it (hrg-compare: delta2, xi1, relative deviation |d*-d0|/|d0|, residual RMS, time).
# Expects a build (the README's main command builds first); BUILD_DIR overrides the build folder.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
bin="$build/bin"
out="$build/out/sim-paper"

for tool in hrg-sim hrg-compare; do
  if [ ! -x "$bin/$tool" ]; then
    echo "main-job: $bin/$tool not found; build first (cmake --build $build)" >&2
    exit 2
  fi
done

mkdir -p "$build/out"
"$bin/hrg-sim" "$root/bench_configs/sim-paper.toml" -o "$out" --force --quiet
"$bin/hrg-compare" "$out" --quiet
echo
echo "The paper prints delta2* = 0.2828944 (deviation 0.057) without xi and xi1* = 0.0100000,"
echo "delta2* = 0.2911010 (deviation 0.030) with its xi1 grid; on exact noise-free data its method"
echo "gives 0.2985732 and 0.3000601 (see MODEL.md: the printed figures could not be reproduced)."
