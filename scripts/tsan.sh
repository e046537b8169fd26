#!/usr/bin/env bash
# ThreadSanitizer run of the tests that share the map or frames between threads: builds
# build-tsan/ (RelWithDebInfo, -fsanitize=thread, no CUDA, no benchmarks) and runs, with one
# OpenMP thread (libgomp is not instrumented: its own barriers would be reported), the snapshot
# test (issue 13, 3), the classification stage's late-result test and the detector workers
# (issue 17: results for frame t fused with frame t's L^p while mapping goes on), and the
# exploration planner thread (issue 18: snapshots and an octree copy while mapping goes on; ~2 min).
#   scripts/tsan.sh [gtest filter for test_pipeline and test_autonomy, default
#                    MapSnapshot.*:ClassificationStage.*:ExplorationLoop.PlannerThread*]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/build-env.sh
BUILD_DIR=${RASM_TSAN_BUILD_DIR:-build-tsan}
FILTER=${1:-MapSnapshot.*:ClassificationStage.*:ExplorationLoop.PlannerThread*}
if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
  cmake -S . -B "$BUILD_DIR" "${RASM_GENERATOR[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRASM_WITH_CUDA=OFF \
    -DRASM_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="-fsanitize=thread" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread"
fi
cmake --build "$BUILD_DIR" -j "$RASM_JOBS" --target test_pipeline test_autonomy test_classification
export OMP_NUM_THREADS=1
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/scripts/tsan.supp"
"$BUILD_DIR/tests/test_pipeline" --gtest_filter="$FILTER"
"$BUILD_DIR/tests/test_autonomy" --gtest_filter="$FILTER"
"$BUILD_DIR/tests/test_classification" --gtest_filter="DetectorWorker.*"
