# Sourced by the build scripts (build.sh, test.sh, fuzz.sh, asan.sh, tsan.sh): the compiler cache
# settings every build of rasm shares, so that a CI run on a fresh clone of a commit the developer
# has already built is mostly cache hits (docs/development.md "Compiler cache").
#   CCACHE_BASEDIR   the checkout: absolute paths under it are hashed as paths relative to the
#                    build folder, so two clones at different places share entries
#   CCACHE_NOHASHDIR the working directory is not hashed (Release builds carry no debug paths)
#   CCACHE_DIR       outside the clone (ccache's default, ~/.cache/ccache), kept unless set
#   CCACHE_SLOPPINESS what ccache may ignore: the build-date macro of BuildInfo.cpp, the times of
#                    files checked out at another moment
#   CCACHE_MAXSIZE   room for a Release, a sanitizer and a fuzz build of a few commits
# RASM_ROOT is the checkout; RASM_JOBS the parallel jobs (default: the cores).
RASM_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
export CCACHE_BASEDIR=$RASM_ROOT  # always this checkout: one inherited from another clone misses
export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-true}
export CCACHE_SLOPPINESS=${CCACHE_SLOPPINESS:-time_macros,include_file_mtime,include_file_ctime}
export CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-12G}
RASM_JOBS=${RASM_JOBS:-$(nproc)}
RASM_GENERATOR=()
command -v ninja >/dev/null && RASM_GENERATOR=(-G Ninja)

# rasm_stage NAME COMMAND...: runs COMMAND, records "NAME seconds status" for rasm_stage_report.
RASM_STAGES=()
rasm_stage() {
  local name=$1 t0=$SECONDS status=0
  shift
  echo "==== stage '$name' ($(date +%H:%M:%S))"
  "$@" || status=$?
  RASM_STAGES+=("$(printf '%-34s %6d s  %s' "$name" $((SECONDS - t0)) \
    "$([[ $status -eq 0 ]] && echo ok || echo "FAILED (exit $status)")")")
  return $status
}
# Prints the stages run so far with their wall times (test.sh calls it on exit, failed or not).
rasm_stage_report() {
  [[ ${#RASM_STAGES[@]} -gt 0 ]] || return 0
  echo "==== stage wall times ($(nproc) cores, RASM_JOBS=$RASM_JOBS)"
  printf '%s\n' "${RASM_STAGES[@]}"
  printf '%-34s %6d s\n' "total" "$SECONDS"
  if command -v ccache >/dev/null; then
    ccache --print-stats 2>/dev/null | awk -F'\t' '$1 ~ /^(direct_cache_hit|preprocessed_cache_hit|cache_miss)$/ { printf "%s %s  ", $1, $2 } END { print "(ccache, since the last zeroing)" }' || true
  fi
}
