#!/usr/bin/env bash
# The formatting check: every C++ file of the tree as clang-format (Debian 12's, 14) and the
# repository's .clang-format write it. Exit 0 when clean; 1 with the files and lines that are not.
#   bash scripts/check-format.sh          check (CI runs it as the ctest test format.clang_format)
#   bash scripts/check-format.sh --fix    rewrite the files in place
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
formatter="$(command -v clang-format-14 || command -v clang-format || true)"
if [ -z "$formatter" ]; then
  echo "check-format: clang-format missing (bash scripts/setup-debian.sh installs it)" >&2
  exit 1
fi
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
  mapfile -t files < <(find src include drivers tests benchmarks -name '*.cpp' -o -name '*.hpp' -o -name '*.h')
fi
if [ "${1:-}" = "--fix" ]; then
  "$formatter" -i "${files[@]}"
  echo "check-format: ${#files[@]} files formatted"
  exit 0
fi
if ! report="$("$formatter" --dry-run --Werror "${files[@]}" 2>&1)"; then
  printf '%s\n' "$report" | grep -E '^[^ ].*(warning|error):' | head -50
  echo "check-format: FAIL: $(printf '%s\n' "$report" | grep -cE 'warning|error:') places differ from .clang-format; bash scripts/check-format.sh --fix" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files match .clang-format"
