#!/usr/bin/env bash
# Builds rasm with its tests and runs every test with ctest (benchmarks are separate: rasm bench).
# In CI (CI=true) with clang installed, also fuzzes each reader for 30 s (scripts/fuzz.sh,
# RASM_FUZZ_SECONDS to change; docs/io.md "Bad input and fuzzing").
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
(
  cd "${RASM_BUILD_DIR:-build}"
  ctest --output-on-failure -j "${RASM_JOBS:-$(nproc)}" --timeout 900
)
if [[ "${CI:-}" == "true" ]] && command -v clang++ >/dev/null; then
  scripts/fuzz.sh "${RASM_FUZZ_SECONDS:-30}"
fi
