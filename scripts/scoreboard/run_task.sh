#!/usr/bin/env bash
# Runs task N of a scoreboard folder: `rasm run <args> --out OUT/runs/<name>`, then the task's
# evals, then one row file OUT/rows/<name>.json (scripts/scoreboard/row.py, written atomically).
# scripts/scoreboard.sh writes OUT/tasks.tsv and OUT/run_task.sh, which calls this with its OUT;
# the same command serves the local loop, GNU parallel and a Slurm array (N = SLURM_ARRAY_TASK_ID).
#   scripts/scoreboard/run_task.sh OUT N
# A task whose row exists is done and skipped (scoreboard.sh clears or refuses old rows before a
# new evaluation). A task whose `needs` path is missing gets a "skipped" row (tried again on the
# next --resume). An interrupted `rasm run` (Ctrl-C, SIGTERM) writes no row and exits 130, so
# --resume runs it again. Environment: RASM (the binary), SCOREBOARD_T0 (epoch s the evaluation
# started, for the progress line's elapsed time), OMP_NUM_THREADS as the caller set it.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT=${1:?usage: run_task.sh OUT N}
N=${2:?usage: run_task.sh OUT N}
RASM=${RASM:-$ROOT/build/rasm}
OUT=$(cd "$OUT" && pwd)
line=$(awk -F'\t' -v n="$N" 'NR > 1 && $1 == n' "$OUT/tasks.tsv")
[[ -n $line ]] || { echo "run_task.sh: no task $N in $OUT/tasks.tsv" >&2; exit 2; }
IFS=$'\t' read -r _ name _ evals _ needs est args <<<"$line"
total=$(($(wc -l <"$OUT/tasks.tsv") - 1))
row=$OUT/rows/$name.json run=$OUT/runs/$name log=$OUT/runs/$name.log
t0=${SCOREBOARD_T0:-$(date +%s)}
elapsed() { local s=$(($(date +%s) - t0)); printf '%d:%02d' $((s / 60)) $((s % 60)); }
progress() {  # what: one line per task start and end
  printf '[%*d/%d] %-36s %s (elapsed %s)\n' ${#total} "$N" "$total" "$name" "$1" "$(elapsed)"
}
row_py() { python3 "$ROOT/scripts/scoreboard/row.py" "$OUT" "$name" "$@"; }
seconds_since() {  # epoch seconds (with decimals): seconds since then, 0.1 s
  python3 -c 'import sys, time; print(round(time.time() - float(sys.argv[1]), 1))' "$1"
}

if [[ -f $row ]] && ! grep -q '"status": "skipped"' "$row"; then
  progress "done earlier"
  exit 0
fi
mkdir -p "$OUT/runs" "$OUT/rows"
if [[ $needs != - ]]; then
  IFS=: read -r -a paths <<<"$needs"
  for p in "${paths[@]}"; do
    if [[ ! -e $p ]]; then
      row_py --status skipped --error "$p not found"
      progress "skipped: $p not found"
      exit 0
    fi
  done
fi

# ---- the run -------------------------------------------------------------------------------------
progress "started (estimated $est s)"
start=$(date +%s.%N)
eval "set -- $args"
cd "$ROOT"  # INI files and their relative paths (../shared/data) are the repository's
echo "task $N ($name): $RASM run $* --out $run --set output.overwrite=true" >"$log"
rc=0
"$RASM" run "$@" --out "$run" --set output.overwrite=true >>"$log" 2>&1 || rc=$?
status=$(python3 -c 'import json, sys
try: print(json.load(open(sys.argv[1])).get("status", "?"))
except Exception: print("none")' "$run/report.json")
if [[ $status == interrupted || $status == aborted || $rc -eq 130 || $rc -eq 143 ]]; then
  progress "interrupted: no row (--resume runs it again)"
  exit 130
fi
if [[ $rc -ne 0 || $status != ok ]]; then
  why=$(grep -v '^frames: ' "$log" | tail -n 1 | cut -c1-300)
  row_py --status failed --wall-s "$(seconds_since "$start")" \
    --error "rasm run exited $rc, report.json status $status: $why (see $log)"
  progress "FAILED: rasm run exited $rc (see $log)"
  exit 0
fi

# ---- the evals: JSON into the run folder, text output to <run>/<eval>.txt; a failing eval is
# recorded in the row's "errors" (its columns stay empty), not fatal ----------------------------
ev_failed=()
evaluate() {  # eval-name command...
  local e=$1
  shift
  "$@" >>"$run/$e.txt" 2>&1 || ev_failed+=("$e")
}
gt=$run/groundtruth.txt est=$run/trajectory.txt
for e in ${evals//,/ }; do
  rm -f "$run/$e.txt"
  case $e in
    track)  # ATE over all frames is report.json's; Sim(3) ATE and RPE over 1 s here
      if [[ -f $gt ]]; then
        evaluate track "$RASM" eval ate "$gt" "$est" --scale --json "$run/ate_sim3.json"
        # RPE needs a run longer than 1 s: its error stays in rpe.txt, not an eval failure
        "$RASM" eval rpe "$gt" "$est" --json "$run/rpe.json" >"$run/rpe.txt" 2>&1 || true
      fi ;;
    seg) evaluate seg "$RASM" eval segmentation "$run" --json "$run/segmentation.json" ;;
    cls) evaluate cls "$RASM" eval classification "$run" --json "$run/classification.json" ;;
    expl)
      evaluate expl "$RASM" eval exploration "$run" --times 60,120,180 \
        --json "$run/exploration_eval.json" ;;
    mem)  # exit 1 = "still growing": a result, not a failure (row.py reads memory.json)
      "$RASM" eval memory "$run" --json "$run/memory.json" >"$run/mem.txt" 2>&1 ||
        [[ $? -eq 1 ]] || ev_failed+=(mem) ;;
    bench)  # the same input, frames decoded first: the frame rate of the mapping alone
      "$RASM" bench "$@" --preload >"$run/bench.json" 2>"$run/bench.txt" || ev_failed+=(bench) ;;
    *) echo "run_task.sh: unknown eval '$e' in task $N" >&2; ev_failed+=("$e") ;;
  esac
done
wall=$(seconds_since "$start")
failed=${ev_failed[*]:-}
row_py --status ok --wall-s "$wall" --eval-failed "${failed// /,}"
if [[ -n $failed ]]; then
  progress "ok in ${wall%.*} s, eval failed: $failed (see $run/<eval>.txt)"
else
  progress "ok in ${wall%.*} s"
fi
