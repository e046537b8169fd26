#!/usr/bin/env bash
# Every tracked C++ file follows .clang-format (scripts/format.sh --check --all). Skipped (77)
# outside a git checkout or without clang-format, except under CI=true, where either is a failure.
set -uo pipefail
root="$1"
cd "$root" || exit 1
if ! command -v clang-format >/dev/null || ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  [[ "${CI:-}" == "true" ]] && { echo "test_format: clang-format or git missing under CI=true" >&2; exit 1; }
  echo "test_format: skipped (needs clang-format and a git checkout)"
  exit 77
fi
if ! out=$(scripts/format.sh --check --all 2>&1); then
  echo "$out" | grep "error:" | cut -d: -f1 | sort -u | sed 's/^/not formatted: /'
  echo "test_format: run scripts/format.sh --all (or scripts/format.sh BASE for the files changed since BASE)"
  exit 1
fi
echo "test_format: every tracked C++ file follows .clang-format"
