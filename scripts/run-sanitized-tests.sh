#!/usr/bin/env bash
# The sanitized build (docs/testing.md "Sanitizers"): the whole project, its tests and every program
# the tests spawn, built with AddressSanitizer and UndefinedBehaviorSanitizer (float-cast-overflow
# too), in its own build folder; then its host tests. Any finding aborts the program that made it,
# so the test that ran it fails and ctest prints the report.
#   bash scripts/run-sanitized-tests.sh          every host test (before an issue closes; ~1 h)
#   bash scripts/run-sanitized-tests.sh --fast   the readers of every input the bench takes (CI)
# SANITIZE_BUILD_DIR (default build-sanitize/) is kept between runs.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SANITIZE_BUILD_DIR:-$root/build-sanitize}"
mode="${1:-all}"
export HRGBENCH_STRICT=1

bash "$root/scripts/setup-debian.sh"
# -O1: the usual sanitizer compromise. RelWithDebInfo's -O2 under ASan makes the Eigen-heavy
# estimator take many minutes per file to compile; -O0 makes its tests 20-50x slower to run.
# -g1: line tables only, all a sanitizer's report needs (file:line in every frame); full debug info
# made this build 7 GB.
cmake -S "$root" -B "$build" -G Ninja -DHRGBENCH_WERROR=ON -DHRGBENCH_SANITIZE=address,undefined \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DHRGBENCH_BUILD_BENCHMARKS=OFF

# detect_leaks: a reader that leaks on a refused input is a finding too. The suppressions name what
# is not ours (none so far: the file says so).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_init_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizer/lsan.supp:print_suppressions=0"

if [ "$mode" = "--fast" ]; then
  # Every reader of a file or request from outside: configs (strict TOML, the loaders, malformed
  # and fuzzed inputs, bounds), the session record and CAN logs, the results URL and store, the
  # estimator's own input checks. Built alone: the rest of the tree is not needed.
  targets=(config_file_toml_reader_test bench_config_malformed_test bench_config_fuzz_test
    config_sim_spec_loader_test session_test session_fuzz_test bench_record_test)
  regex="^($(IFS='|'; echo "${targets[*]}"))\\."
  cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"
  listing="$(ctest --test-dir "$build" -N -R "$regex")"
  count="$(grep -c 'Test *#' <<<"$listing" || true)"
  for target in "${targets[@]}"; do
    grep -q " ${target}\\." <<<"$listing" || {
      echo "run-sanitized-tests: FAIL: no tests found in $target" >&2
      exit 1
    }
  done
  echo "run-sanitized-tests: $count sanitized tests of ${#targets[@]} programs (the readers of every input)"
  ctest --test-dir "$build" --output-on-failure -j "$(nproc)" --timeout 900 -R "$regex"
else
  cmake --build "$build" -j "$(nproc)"
  echo "run-sanitized-tests: every host test, sanitized"
  ctest --test-dir "$build" --output-on-failure -j "$(nproc)" --timeout 1800 -LE 'kernel|vm_guest'
fi
echo "run-sanitized-tests: clean (no sanitizer finding, every test passed)"
