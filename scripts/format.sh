#!/usr/bin/env bash
# clang-format (.clang-format: Google, 100 columns) over the C++ files changed against a base
# commit (default HEAD~1), or every tracked C++ file with --all; --check only reports.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "format.sh: clang-format not found (apt-get install clang-format)" >&2; exit 2; }
check=0 all=0 base=HEAD~1
for a in "$@"; do
  case $a in --check) check=1 ;; --all) all=1 ;; *) base=$a ;; esac
done
if [[ $all -eq 1 ]]; then
  mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.cu' '*.cuh' '*.hpp')
else
  mapfile -t files < <(git diff --name-only --diff-filter=ACMR "$base" -- '*.cpp' '*.h' '*.cu' '*.cuh' '*.hpp')
fi
[[ ${#files[@]} -gt 0 ]] || exit 0
if [[ $check -eq 1 ]]; then clang-format --dry-run -Werror "${files[@]}"; else clang-format -i "${files[@]}"; fi
