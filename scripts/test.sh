#!/usr/bin/env bash
# Builds rasm with its tests and benchmarks and runs every test with ctest (the README's test
# command; .ci/run runs exactly this). With CI=true (or RASM_SANITIZE=1) a second stage follows:
# one clang build of the code that reads untrusted input and of the kernels with AddressSanitizer,
# UndefinedBehaviorSanitizer and libFuzzer's coverage (build-fuzz/, CMake RASM_FUZZ=ON), in which
# each reader's fuzzer runs for RASM_FUZZ_SECONDS (default 20) and the unit tests of those modules
# run under the sanitizers (scripts/fuzz.sh --tests). The sanitizer runs of the whole suite are
# scripts a developer runs when touching memory or threads: scripts/asan.sh, scripts/tsan.sh.
# Prints the wall time of each stage at the end, failed or not (docs/development.md "CI").
#   RASM_SANITIZE=0 skips the sanitizer stage in CI; RASM_SANITIZE=1 runs it outside CI.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/build-env.sh
trap rasm_stage_report EXIT
command -v ccache >/dev/null && ccache -z >/dev/null

rasm_stage "build (Release, all targets)" scripts/build.sh --all
run_ctest() (
  cd "${RASM_BUILD_DIR:-build}"
  ctest --output-on-failure -j "$RASM_JOBS" --timeout 900
)
rasm_stage "ctest (Release)" run_ctest

sanitize=${RASM_SANITIZE:-}
[[ -z $sanitize && "${CI:-}" == "true" ]] && sanitize=1
if [[ $sanitize == 1 || $sanitize == true ]]; then
  if command -v clang++ >/dev/null; then
    rasm_stage "sanitizer build (clang, build-fuzz)" scripts/fuzz.sh --build
    rasm_stage "fuzz (each reader ${RASM_FUZZ_SECONDS:-20} s)" scripts/fuzz.sh "${RASM_FUZZ_SECONDS:-20}"
    rasm_stage "sanitizer unit tests (build-fuzz)" scripts/fuzz.sh --tests
  else
    echo "test.sh: clang++ not found: sanitizer stage skipped (scripts/install-deps.sh installs it)" >&2
    exit 1
  fi
fi
