#!/usr/bin/env bash
# Builds rasm with its tests and runs every test with ctest (benchmarks are separate: rasm bench).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
cd "${RASM_BUILD_DIR:-build}"
ctest --output-on-failure -j "${RASM_JOBS:-$(nproc)}" --timeout 900
