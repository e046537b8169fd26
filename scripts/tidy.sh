#!/usr/bin/env bash
# Runs clang-tidy (.clang-tidy: bugprone, performance, modernize) over the C++ sources changed
# against a base commit (default HEAD~1; `scripts/tidy.sh main~5`, or `--all` for every source),
# with the compile commands of the build folder (configured with CMAKE_EXPORT_COMPILE_COMMANDS).
# CUDA files are skipped (clang-tidy cannot use nvcc's flags). Exit code 1 when it reports.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${RASM_BUILD_DIR:-build}
command -v clang-tidy >/dev/null || { echo "tidy.sh: clang-tidy not found (apt-get install clang-tidy)" >&2; exit 2; }
if [[ ! -f "$BUILD_DIR/compile_commands.json" ]]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > /dev/null
fi
if [[ "${1:-}" == "--all" ]]; then
  mapfile -t files < <(git ls-files 'modules/*.cpp' 'app/*.cpp' 'tests/*.cpp')
else
  base=${1:-HEAD~1}
  mapfile -t files < <(git diff --name-only --diff-filter=ACMR "$base" -- '*.cpp' | grep -E '^(modules|app|tests)/' || true)
fi
[[ ${#files[@]} -gt 0 ]] || { echo "tidy.sh: no changed C++ sources"; exit 0; }
echo "tidy.sh: ${#files[@]} file(s)" >&2
status=0
for f in "${files[@]}"; do
  clang-tidy -p "$BUILD_DIR" --quiet "$f" 2>/dev/null | grep -E "warning:|error:" -A3 && status=1
done
exit $status
