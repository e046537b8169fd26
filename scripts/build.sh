#!/usr/bin/env bash
# Configures build/ (Release, Ninja, ccache; scripts/lib/build-env.sh) on first use and builds what
# `rasm run` needs: the rasm binary and its modules. --all builds every target (test suites,
# benchmarks, the device-check tools), as scripts/test.sh does. Other arguments go to CMake, e.g.
#   scripts/build.sh -DRASM_ARCH=native -DRASM_WITH_CUDA=OFF
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/build-env.sh
BUILD_DIR=${RASM_BUILD_DIR:-build}
targets=(--target rasm)
args=()
for a in "$@"; do
  if [[ $a == --all ]]; then targets=(); else args+=("$a"); fi
done
if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
  cmake -S . -B "$BUILD_DIR" "${RASM_GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release "${args[@]}"
elif [[ ${#args[@]} -gt 0 ]]; then
  cmake -S . -B "$BUILD_DIR" "${args[@]}"
fi
cmake --build "$BUILD_DIR" -j "$RASM_JOBS" "${targets[@]}"
