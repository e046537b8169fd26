#!/bin/bash
# ctest build_without_sim: the product without the simulator. Configures BUILD_DIR-nosim (a
# sibling of the build folder, so that ccache's relative paths match and the unchanged sources hit
# the main build's cache) with -DRASM_WITH_SIM=OFF and the main build's generator, build type,
# -march and CUDA setting, builds only the rasm binary and its libraries, then checks that none
# of them links Embree or assimp, that a real sequence runs and that the embedded default (a
# simulated run) and `rasm sim` say that the simulator is missing.
# usage: build_without_sim.sh BUILD_DIR SOURCE_DIR GENERATOR BUILD_TYPE ARCH WITH_CUDA
set -euo pipefail
build=$1 src=$2 generator=$3 build_type=$4 arch=$5 cuda=$6
scratch=$build-nosim
fail() { echo "build_without_sim: $*" >&2; exit 1; }
t0=$(date +%s)
mkdir -p "$scratch"
cmake -S "$src" -B "$scratch" -G "$generator" -DCMAKE_BUILD_TYPE="$build_type" \
  -DRASM_ARCH="$arch" -DRASM_WITH_CUDA="$cuda" -DRASM_WITH_SIM=OFF -DRASM_BUILD_TESTS=OFF \
  -DRASM_BUILD_BENCH=OFF > "$scratch/configure.log" 2>&1 ||
  { cat "$scratch/configure.log"; fail "configure failed"; }
cmake --build "$scratch" -j "${RASM_JOBS:-$(nproc)}" --target rasm ||
  fail "building rasm with -DRASM_WITH_SIM=OFF failed"
echo "build_without_sim: configured and built in $(($(date +%s) - t0)) s"
rasm=$scratch/rasm
linked=$(ldd "$rasm" | grep -i embree || true)
[[ -z $linked ]] || fail "rasm built without the simulator still loads Embree: $linked"
# (libassimp is still loaded: MRPT's own libmrpt-opengl needs it; no rasm library does.)
for f in "$rasm" "$scratch"/modules/*/librasm_*.so; do
  direct=$(readelf -d "$f" | grep -i -E 'NEEDED.*(embree|assimp)' || true)
  [[ -z $direct ]] || fail "$f built without the simulator still links: $direct"
done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# A real sequence (the shipped rawlog) maps as in the default build.
"$rasm" run "$src/rawlogs/sim_office_handheld_320x240.rawlog" --max-frames 3 --out "$out/run" \
  > "$out/run.log" 2>&1 || { cat "$out/run.log"; fail "a run on the shipped rawlog failed"; }
grep -q '"status": "ok"' "$out/run/report.json" || fail "report.json of the rawlog run is not ok"
# The embedded default is a simulated run: an InputError (exit 3) that says what to do instead.
status=0
msg=$("$rasm" run --out "$out/default" 2>&1) || status=$?
[[ $status == 3 ]] || fail "rasm run (the simulated default) exited $status, expected 3: $msg"
grep -q 'built without the simulator (-DRASM_WITH_SIM=OFF): give a real source' <<< "$msg" ||
  fail "rasm run (the simulated default) does not say the simulator is missing: $msg"
status=0
msg=$("$rasm" sim info office 2>&1) || status=$?
[[ $status != 0 ]] && grep -q 'RASM_WITH_SIM=OFF' <<< "$msg" ||
  fail "rasm sim does not say the simulator is missing: $msg"
# A [sim_detector] section (an INI written for a simulated run) names what is missing.
status=0
msg=$("$rasm" run "$src/rawlogs/sim_office_handheld_320x240.rawlog" --max-frames 3 \
  --set sim_detector.p_max=0.5 --out "$out/simdet" 2>&1) || status=$?
[[ $status == 3 ]] && grep -q '\[sim_detector\].*RASM_WITH_SIM=OFF' <<< "$msg" ||
  fail "a [sim_detector] section without the simulator: exit $status, $msg"
echo "build_without_sim: ok"
