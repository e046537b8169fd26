#!/usr/bin/env bash
# Builds the libFuzzer targets of the readers (clang, RASM_FUZZ=ON, in build-fuzz/: only the
# modules they need) and runs each for SECONDS (default 60) from a seed corpus made of the
# project's own files (fuzz_seeds). docs/io.md "Bad input and fuzzing".
#   scripts/fuzz.sh [seconds] [target ...]     targets: rawlog config world trajectory surfelmap
# Findings (crash-*, oom-*, timeout-*, leak-*) go to build-fuzz/findings/<target>/; the corpus
# grows in build-fuzz/corpus/<target>/ and is reused by the next run. Exit 1 on any finding.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-60}
shift || true
TARGETS=("$@")
[[ ${#TARGETS[@]} -eq 0 ]] && TARGETS=(rawlog config world trajectory surfelmap)
BUILD_DIR=${RASM_FUZZ_BUILD_DIR:-build-fuzz}
JOBS=${RASM_JOBS:-$(nproc)}
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (scripts/install-deps.sh)" >&2; exit 2; }
GEN=()
command -v ninja >/dev/null && GEN=(-G Ninja)
if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
  CC=clang CXX=clang++ cmake -S . -B "$BUILD_DIR" "${GEN[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DRASM_FUZZ=ON -DRASM_WITH_CUDA=OFF
fi
cmake --build "$BUILD_DIR" -j "$JOBS"

# Leaks in MRPT's class registry and OpenMP's thread pool at exit are not the readers'.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=0:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export OMP_NUM_THREADS=1
"$BUILD_DIR/fuzz/fuzz_seeds" . "$BUILD_DIR/seeds" >/dev/null
status=0
for t in "${TARGETS[@]}"; do
  corpus="$BUILD_DIR/corpus/$t" findings="$BUILD_DIR/findings/$t"
  mkdir -p "$corpus" "$findings"
  cp -n "$BUILD_DIR/seeds/$t"/* "$corpus/" 2>/dev/null || true
  log="$BUILD_DIR/findings/$t.log"
  echo "fuzz.sh: fuzz_$t for ${SECONDS_EACH} s (corpus $corpus, log $log)"
  # -rss_limit_mb / -malloc_limit_mb: a size field taken on trust (GBs for a corrupt header)
  # is a finding; -timeout: a hang is one too. MRPT's own size fields are bounded by
  # modules/io/src/MrptSizeLimits.cpp (docs/io.md "Bad input and fuzzing").
  limit_mb=1024
  if ! "$BUILD_DIR/fuzz/fuzz_$t" "$corpus" -max_total_time="$SECONDS_EACH" -timeout=10 \
      -rss_limit_mb=$((limit_mb * 2)) -malloc_limit_mb=$limit_mb -max_len=262144 -print_final_stats=1 \
      -artifact_prefix="$findings/" >"$log" 2>&1; then
    echo "fuzz.sh: fuzz_$t FOUND A PROBLEM (see $log and $findings/)" >&2
    tail -40 "$log" >&2
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" | tr '\n' ' ' | sed "s/^/fuzz.sh: fuzz_$t /"
  echo
done
exit $status
