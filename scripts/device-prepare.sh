#!/usr/bin/env bash
# Prepares the device check (docs/device-check.md) on a CPU machine with the normal build:
#   device/vendor/eigen3/  Eigen's dense headers (the GPU machine has no Eigen)
#   device/data/           real inputs (tests/device/DeviceData.h) dumped from a 7-Scenes sequence
# Both are git-ignored (/device/); a device run carries them: carry=["device/vendor","device/data"].
# Then `scripts/device-check.sh --dry-run` checks them here.
#
# Environment: RASM_BUILD_DIR (build), RASM_JOBS, RASM_SHARED_DATA (../shared/data),
# RASM_DEVICE_SEQUENCE (7-Scenes folder, default redkitchen_first300), RASM_DEVICE_FRAME (60:
# the map of frames 0-59, ~420k surfels), EIGEN_INCLUDE (/usr/include/eigen3).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${RASM_BUILD_DIR:-build}
JOBS=${RASM_JOBS:-$(nproc)}
DATA=${RASM_SHARED_DATA:-../shared/data}
SEQ=${RASM_DEVICE_SEQUENCE:-$DATA/7scenes/redkitchen_first300}
FRAME=${RASM_DEVICE_FRAME:-60}
EIGEN=${EIGEN_INCLUDE:-/usr/include/eigen3}
LIMIT_MIB=60  # what may travel: 64 MiB of ignored paths in all, keep a margin

[[ -d "$SEQ" ]] || { echo "device-prepare: no 7-Scenes sequence at $SEQ" >&2; exit 1; }
[[ -f "$EIGEN/Eigen/Core" ]] || { echo "device-prepare: no Eigen headers at $EIGEN" >&2; exit 1; }

# 1. Eigen: the dense modules only (no sparse solvers, no LAPACKE bindings), with its licence.
rm -rf device/vendor
mkdir -p device/vendor/eigen3/Eigen/src
for m in Core Dense LU Cholesky QR SVD Geometry Eigenvalues Householder Jacobi StdVector StdDeque; do
  cp "$EIGEN/Eigen/$m" device/vendor/eigen3/Eigen/
done
for d in Core LU Cholesky QR SVD Geometry Eigenvalues Householder Jacobi StlSupport plugins misc; do
  cp -r "$EIGEN/Eigen/src/$d" device/vendor/eigen3/Eigen/src/
done
rm -f device/vendor/eigen3/Eigen/src/misc/lapacke*.h
for f in /usr/share/doc/libeigen3-dev/copyright "$EIGEN/COPYING.MPL2"; do
  [[ -f "$f" ]] && cp "$f" device/vendor/eigen3/ && break
done
grep -h "define EIGEN_[A-Z]*_VERSION" "$EIGEN/Eigen/src/Core/util/Macros.h" | head -3 > device/vendor/eigen3/VERSION

# 2. The dumper, in the normal build (configured on first use as scripts/build.sh does).
if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
  GEN=()
  command -v ninja >/dev/null && GEN=(-G Ninja)
  cmake -S . -B "$BUILD_DIR" "${GEN[@]}" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" -j "$JOBS" --target device_dump_inputs

# 3. The inputs.
rm -rf device/data
"$BUILD_DIR/tests/device/device_dump_inputs" "$SEQ" device/data --frame "$FRAME"
commit=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- modules tests/device || commit="$commit+local-changes"
echo "dump_commit $commit" >> device/data/meta.txt

# 4. Sizes: what a device run carries.
du -sh device/vendor device/data
total=$(( ($(du -sb device/vendor | cut -f1) + $(du -sb device/data | cut -f1)) / 1048576 ))
echo "device-prepare: carried ignored paths ${total} MiB (limit ${LIMIT_MIB}); working tree $(git ls-files -z | du -ch --files0-from=- | tail -1 | cut -f1)"
if (( total > LIMIT_MIB )); then
  echo "device-prepare: over ${LIMIT_MIB} MiB: dump an earlier frame (RASM_DEVICE_FRAME)" >&2
  exit 1
fi
