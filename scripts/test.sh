#!/usr/bin/env bash
# Builds rasm with its tests and runs every test with ctest (benchmarks are separate: rasm bench).
# In CI (CI=true) with clang installed, also fuzzes each reader for 30 s (scripts/fuzz.sh,
# RASM_FUZZ_SECONDS to change; docs/io.md "Bad input and fuzzing"), then runs the unit tests
# under ASan + UBSan (scripts/asan.sh).
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
# In CI, the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer (and
# LeakSanitizer) in build-asan/ (scripts/asan.sh; RASM_ASAN=0 skips it, RASM_ASAN=1 runs it
# outside CI too).
if [[ "${RASM_ASAN:-${CI:-}}" == "true" || "${RASM_ASAN:-}" == "1" ]]; then
  scripts/asan.sh
fi
