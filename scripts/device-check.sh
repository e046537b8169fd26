#!/usr/bin/env bash
# The device check (docs/device-check.md): builds tests/device/device_check.cpp with the modules'
# CUDA launchers (modules/*/cuda/*.cu) using nvcc alone, runs every launcher against the same
# kernel on the CPU on the inputs in device/data, and prints one JSON summary (also written to
# $OUT/device-check.json when $OUT is set). Needs only nvcc, a host C++ compiler, the working tree
# and the carried device/vendor (Eigen) and device/data (scripts/device-prepare.sh).
#
#   scripts/device-check.sh                 on the GPU machine: nvcc build for sm_$RASM_DEVICE_ARCH, run
#   scripts/device-check.sh --dry-run       host compiler only: the CPU side, compared exactly
#   scripts/device-check.sh --compile-only  nvcc build only (proves the CUDA build here)
#
# Environment: NVCC (else PATH, /usr/local/cuda/bin), CXX (g++), RASM_DEVICE_ARCH (90),
# RASM_DEVICE_REPS (10), RASM_DEVICE_DATA (device/data).
# Exit status: the program's (0 pass, 1 a check failed, 2 error, 3 no GPU found), 2 when the
# build fails, 124 on a timeout. Bounded: 240 s to build, 240 s to run.
set -uo pipefail
cd "$(dirname "$0")/.."
MODE=cuda
case "${1:-}" in
  --dry-run | --cpu) MODE=cpu ;;
  --compile-only) MODE=compile ;;
  "") ;;
  *) echo "usage: $0 [--dry-run | --compile-only]" >&2; exit 2 ;;
esac
ARCH=${RASM_DEVICE_ARCH:-90}
REPS=${RASM_DEVICE_REPS:-10}
DATA=${RASM_DEVICE_DATA:-device/data}
VENDOR=device/vendor/eigen3
BUILD=device/build-$MODE
[[ $MODE == compile ]] && BUILD=device/build-cuda
LOG=$BUILD/build.log
T0=$(date +%s)

json_escape() { sed -e 's/\\/\\\\/g' -e 's/"/\\"/g' -e 's/\t/ /g' | awk '{printf "%s\\n", $0}'; }
fail_json() {  # message, log file (optional), exit status
  local tail=""
  [[ -n "${2:-}" && -f "$2" ]] && tail=$(tail -c 4000 "$2" | json_escape)
  local j="{\"check\": \"rasm device-check\", \"pass\": false, \"error\": \"$1\", \"log_tail\": \"$tail\"}"
  echo "$j"
  [[ -n "${OUT:-}" ]] && echo "$j" > "$OUT/device-check.json"
  exit "$3"
}

[[ -f "$VENDOR/Eigen/Core" ]] || fail_json "no $VENDOR: run scripts/device-prepare.sh on a CPU machine and carry device/vendor" "" 2
[[ $MODE == compile || -f "$DATA/meta.txt" ]] || fail_json "no $DATA/meta.txt: run scripts/device-prepare.sh and carry device/data" "" 2

INC=(-Itests/device "-I$VENDOR")
for d in modules/*/include; do INC+=("-I$d"); done
CXX=${CXX:-g++}
HOSTFLAGS=(-O3 -DNDEBUG -ffp-contract=off)  # no FMA contraction on any host, as x86-64-v2 builds
[[ $(uname -m) == x86_64 ]] && HOSTFLAGS+=(-march=x86-64-v2)
# OpenMP when the host compiler has it (the CPU reference is then multi-threaded).
if echo 'int main(){}' | "$CXX" -x c++ -fopenmp - -o /dev/null 2>/dev/null; then HOSTFLAGS+=(-fopenmp); OMP=(-lgomp); else OMP=(); fi
mkdir -p "$BUILD"
: > "$LOG"

if [[ $MODE == cpu ]]; then
  SRCS=(tests/device/device_check.cpp tests/device/cpu_stubs.cpp)
  COMPILE=("$CXX" -std=c++17 "${HOSTFLAGS[@]}" "${INC[@]}")
  LINK=("$CXX" "${HOSTFLAGS[@]}")
  COMPILER="$("$CXX" --version 2>/dev/null | head -1)"
else
  NVCC=${NVCC:-$(command -v nvcc || true)}
  [[ -z "$NVCC" ]] && for c in /usr/local/cuda/bin/nvcc /usr/local/cuda-*/bin/nvcc; do [[ -x $c ]] && NVCC=$c && break; done
  [[ -x "$NVCC" ]] || fail_json "nvcc not found (set NVCC)" "" 2
  XHOST=$(IFS=,; echo "${HOSTFLAGS[*]}")
  # The flags the *_cuda targets get from the top-level CMakeLists.txt, for sm_$ARCH.
  NVFLAGS=(-std=c++17 -O3 -DNDEBUG "-arch=sm_$ARCH" --expt-relaxed-constexpr
           -diag-suppress 20012,20014,20015,554 -DRASM_DEVICE_CHECK_CUDA -Xcompiler "$XHOST")
  SRCS=(modules/core/cuda/FrameKernels.cu modules/surfel_map/cuda/SurfelRender.cu
        modules/tracking/cuda/IcpReduce.cu modules/fusion/cuda/FusionKernels.cu
        tests/device/device_kernels.cu tests/device/device_check.cpp)
  COMPILE=("$NVCC" "${NVFLAGS[@]}" "${INC[@]}")
  LINK=("$NVCC" "-arch=sm_$ARCH" -Xcompiler "$XHOST")
  COMPILER="$("$NVCC" --version 2>/dev/null | tail -2 | head -1)"
fi

# Build: every translation unit in parallel, then link.
pids=()
objs=()
for s in "${SRCS[@]}"; do
  o="$BUILD/$(basename "$s").o"
  objs+=("$o")
  timeout 240 "${COMPILE[@]}" -c "$s" -o "$o" > "$BUILD/$(basename "$s").log" 2>&1 &
  pids+=($!)
done
status=0
for i in "${!pids[@]}"; do
  if ! wait "${pids[$i]}"; then status=1; echo "== FAILED ${SRCS[$i]}" >> "$LOG"; fi
  cat "$BUILD/$(basename "${SRCS[$i]}").log" >> "$LOG"
done
[[ $status == 0 ]] || fail_json "build failed ($COMPILER)" "$LOG" 2
"${LINK[@]}" "${objs[@]}" -o "$BUILD/device_check" "${OMP[@]}" >> "$LOG" 2>&1 || fail_json "link failed ($COMPILER)" "$LOG" 2
BUILD_S=$(( $(date +%s) - T0 ))
[[ -n "${OUT:-}" ]] && cp "$LOG" "$OUT/device-check-build.log"

if [[ $MODE == compile ]]; then
  j="{\"check\": \"rasm device-check\", \"compile_only\": true, \"pass\": true, \"compiler\": \"$COMPILER\", \"arch\": \"sm_$ARCH\", \"build_s\": $BUILD_S, \"binary\": \"$BUILD/device_check\"}"
  echo "$j"
  exit 0
fi

ARGS=("$DATA" --reps "$REPS" --build-info "$COMPILER; built in ${BUILD_S} s")
[[ -n "${OUT:-}" ]] && ARGS+=(--json "$OUT/device-check.json")
timeout 240 "$BUILD/device_check" "${ARGS[@]}" 2> "$BUILD/run.err"
rc=$?
if (( rc == 124 || rc > 128 )); then
  [[ -n "${OUT:-}" ]] && cp "$BUILD/run.err" "$OUT/device-check-run.err"
  fail_json "device_check did not finish (status $rc)" "$BUILD/run.err" "$rc"
fi
exit $rc
