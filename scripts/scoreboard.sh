#!/usr/bin/env bash
# The scoreboard: one command, one results table for the code as it is now (docs/scoreboard.md).
# Tracking (ATE over all frames, fraction tracked, silent frames, unaligned world-frame error of
# simulated runs), segmentation (objects recovered, PQ), classification (object accuracy),
# exploration (coverage and objects correct at 60 / 120 / 180 s per planner), frame rate and peak
# memory, on the real sequences of ../shared/data, the shipped simulated worlds and rooms of
# `rasm sim generate --seed 1001..` nobody tuned on. Writes docs/results.md (one table per group)
# and docs/results.json, and says what got better or worse beyond noise against the committed
# docs/results.json of the same panel.
#
#   scripts/scoreboard.sh [--smoke | --quick | --full | --planners | --flats | --worldframe] [--out DIR] [--resume | --fresh]
#       [--jobs J] [--only REGEX] [--dry-run] [--gather]
#       [--compare PREV.json | --no-compare] [--out-md FILE] [--out-json FILE] [--no-docs]
#       [--slurm FILE.sbatch [--slurm-time 02:00:00] [--slurm-cpus 2] [--slurm-mem 8G]
#        [--sbatch "--partition=x"]...] [-- --set section.key=value ...]
#
# Panels (scripts/scoreboard/panels.py lists their tasks; docs/scoreboard.md "Cost"):
#   --smoke  every group and eval on 10-20 frames and 10 s explorations, 160x120: ~2 min; writes
#            its table to DIR/results.md only (never docs/)
#   --quick  real sequences, shipped worlds and one generated room at 320x240, ig and random
#            exploring for 120 s: ~11 min on 2 cores
#   --full   (default) 640x480, ten generated rooms, every planner on the shipped worlds, two
#            generated rooms and two flats for 240 s on tracked poses, kidnapping, 24 memory
#            laps: hours on 2 cores; made for --jobs or --slurm
#   --planners  the exploration planners alone: every planner (oracle included) on the shipped
#            worlds, three generated rooms and four flats, true poses, 160x120, 240 s: ~1 h;
#            its table goes to DIR/results.md (give --out-md docs/results-planners.md)
#   --flats  ig, ig before the frontier changes of 2026-12-07 and the oracle on seven flats of 3-4
#            rooms at 640x480, true poses, 240 s: ~2.5 h (docs/exploration.md "Rooms off the
#            hallway"); scripts/scoreboard/planners_summary.py DIR tabulates it
#   --worldframe  the map in the world frame while exploring: ig on five generated rooms, five
#            flats and two_rooms, 320x240, 180 s, tracked and true poses, two seeds: ~1.5 h;
#            scripts/scoreboard/worldframe_summary.py DIR states the targets
# --out DIR: the run folders (default eval_out/scoreboard-<panel>): tasks.tsv (one line per task:
#   name, group, evals, pool, needs, estimate, rasm run arguments), runs/<task>/ (the run and its
#   evals' JSON), runs/<task>.log, rows/<task>.json (one per finished task, written atomically),
#   results.md / results.json. A DIR that already holds rows is refused unless --resume (skip the
#   tasks whose row exists: an interrupted evaluation loses only the task in progress) or --fresh
#   (delete them and start over).
# --jobs J: J tasks at once through GNU parallel, each with OMP_NUM_THREADS = cores / J unless
#   set (default 1: one task after another with every core). --only REGEX: only the tasks whose
#   name matches (implies --no-docs). --dry-run: write the task list, print it with the estimated
#   cost, run nothing. --gather: only rebuild the table from DIR's rows (after a Slurm job).
# --compare PREV.json: what got better or worse beyond the noise thresholds against an earlier
#   results.json (default: the committed docs/results.json when it holds the same panel kind);
#   --no-compare skips it. --out-md / --out-json: where the table goes (default docs/results.md and
#   docs/results.json for --quick and --full); --no-docs: only DIR/results.md and .json.
# --slurm FILE.sbatch: write a Slurm array job (one task per SLURM_ARRAY_TASK_ID, the same
#   DIR/run_task.sh N as the local run) and run nothing; afterwards
#   `scripts/scoreboard.sh --out DIR --gather` makes the table.
# Arguments after -- go to every `rasm run` (e.g. -- --set tracking.icp_max_iterations=20).
# RASM=path/to/rasm overrides the binary (default build/rasm); RASM_SHARED_DATA the data folder
# (default ../shared/data; tasks whose data is absent are skipped with a message).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
RASM=${RASM:-build/rasm}
DATA=${RASM_SHARED_DATA:-../shared/data}
panel="" out="" resume=0 fresh=0 jobs=1 only="" dry=0 gather_only=0 compare=auto
out_md="" out_json="" no_docs=0 slurm="" slurm_time=02:00:00 slurm_cpus=2 slurm_mem=8G
sbatch_extra=() extra=()
command_line="scripts/scoreboard.sh${*:+ $*}"
die() { echo "scoreboard.sh: $*" >&2; exit 2; }
need() { [[ $# -ge 2 ]] || die "$1 needs a value"; }
while [[ $# -gt 0 ]]; do
  case $1 in
    --smoke | --quick | --full | --planners | --flats | --worldframe)
      [[ -z $panel || $panel == "${1#--}" ]] || die "--$panel and $1 exclude each other"
      panel=${1#--} ;;
    --out) need "$@"; out=$2; shift ;;
    --resume) resume=1 ;;
    --fresh) fresh=1 ;;
    --jobs) need "$@"; jobs=$2; shift ;;
    --only) need "$@"; only=$2; shift ;;
    --dry-run) dry=1 ;;
    --gather) gather_only=1 ;;
    --compare) need "$@"; compare=$2; shift ;;
    --no-compare) compare=none ;;
    --out-md) need "$@"; out_md=$2; shift ;;
    --out-json) need "$@"; out_json=$2; shift ;;
    --no-docs) no_docs=1 ;;
    --slurm) need "$@"; slurm=$2; shift ;;
    --slurm-time) need "$@"; slurm_time=$2; shift ;;
    --slurm-cpus) need "$@"; slurm_cpus=$2; shift ;;
    --slurm-mem) need "$@"; slurm_mem=$2; shift ;;
    --sbatch) need "$@"; sbatch_extra+=("$2"); shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    *) die "unknown option '$1' (scripts/scoreboard.sh --help)" ;;
  esac
  shift
done
[[ $jobs =~ ^[1-9][0-9]*$ ]] || die "--jobs '$jobs': expected a whole number >= 1"
[[ $slurm_cpus =~ ^[1-9][0-9]*$ ]] || die "--slurm-cpus '$slurm_cpus': expected a whole number >= 1"
[[ $resume -eq 1 && $fresh -eq 1 ]] && die "--resume and --fresh exclude each other"
[[ $dry -eq 1 && $fresh -eq 1 ]] && die "--dry-run deletes nothing: drop --fresh"
[[ $compare == auto || $compare == none || -f $compare ]] ||
  die "--compare '$compare': no such file (expected an earlier results.json)"
if [[ -n $only ]]; then
  # a bad regex makes [[ =~ ]] return 2: check it once here
  rc=0; [[ x =~ $only ]] || rc=$?
  [[ $rc -le 1 ]] || die "--only '$only': not a valid regular expression"
fi
[[ -x $RASM ]] || die "no rasm binary at $RASM (scripts/build.sh, or set RASM=path/to/rasm)"
RASM=$(cd "$(dirname "$RASM")" && pwd)/$(basename "$RASM")
command -v python3 >/dev/null || die "python3 not found"
if [[ $jobs -gt 1 && -z $slurm && $dry -eq 0 && $gather_only -eq 0 ]]; then
  command -v parallel >/dev/null ||
    die "--jobs $jobs needs GNU parallel (scripts/install-deps.sh installs it)"
fi
out=${out:-eval_out/scoreboard-${panel:-full}}
mkdir -p "$out"
out=$(cd "$out" && pwd)
# The panel of an earlier evaluation in DIR (--gather and --resume continue it).
old_panel=""
if [[ -f $out/scoreboard.json ]]; then
  old_panel=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["panel"] or "")' \
    "$out/scoreboard.json")
fi
[[ $gather_only -eq 1 && -z $panel ]] && panel=$old_panel
panel=${panel:-full}
# Where the table goes: docs/ for the quick and full panels, unless told otherwise.
if [[ $panel == smoke || $panel == planners || $panel == flats || $panel == worldframe ||
      $no_docs -eq 1 || -n $only ]]; then
  docs_md="" docs_json=""
else
  docs_md=$ROOT/docs/results.md docs_json=$ROOT/docs/results.json
fi
[[ -n $out_md ]] && docs_md=$out_md
[[ -n $out_json ]] && docs_json=$out_json
gather() {
  local args=(--compare "$compare")
  [[ -n $docs_md ]] && args+=(--out-md "$docs_md")
  [[ -n $docs_json ]] && args+=(--out-json "$docs_json")
  python3 "$ROOT/scripts/scoreboard/gather.py" "$out" "${args[@]}"
}
if [[ $gather_only -eq 1 ]]; then
  [[ -f $out/tasks.tsv ]] || die "$out has no tasks.tsv: nothing to gather"
  [[ -z $old_panel || $old_panel == "$panel" ]] || die "$out holds a $old_panel panel, not $panel"
  gather
  exit 0
fi

# ---- an earlier evaluation in DIR: resume it, clear it, or refuse --------------------------------
shopt -s nullglob
old_rows=("$out"/rows/*.json)
shopt -u nullglob
if [[ ${#old_rows[@]} -gt 0 && $resume -eq 0 ]]; then
  [[ $fresh -eq 1 ]] ||
    die "$out already holds ${#old_rows[@]} rows of an earlier evaluation: --resume continues it," \
      "--fresh deletes it and starts over (or --out another folder)"
  rm -rf "$out/runs" "$out/rows" "$out/worlds" "$out/slurm" "$out/tasks.tsv" "$out/run_task.sh" \
    "$out/scoreboard.json" "$out/results.md" "$out/results.json" "$out/joblog.tsv"
fi
resume_arg=()
if [[ $resume -eq 1 && -n $old_panel ]]; then
  [[ $old_panel == "$panel" ]] ||
    die "$out holds a $old_panel panel, not $panel: --$old_panel --resume continues it," \
      "--fresh starts over"
  resume_arg=(--resume)
fi
[[ -n ${OMP_NUM_THREADS:-} ]] ||
  export OMP_NUM_THREADS=$(($(nproc) / jobs > 0 ? $(nproc) / jobs : 1))
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}

# ---- the task list (generates the rooms of rasm sim generate into DIR/worlds once) ---------------
python3 "$ROOT/scripts/scoreboard/panels.py" "$panel" "$out" "$RASM" "$DATA" -- "${extra[@]}"
n=$(($(wc -l <"$out/tasks.tsv") - 1))
cat >"$out/run_task.sh" <<EOF
#!/usr/bin/env bash
# Generated by scripts/scoreboard.sh: runs task N (1..$n) of tasks.tsv in this folder, the same way
# locally, under GNU parallel and under Slurm (scripts/scoreboard/run_task.sh).
export RASM=\${RASM:-$(printf '%q' "$RASM")}
exec bash $(printf '%q' "$ROOT/scripts/scoreboard/run_task.sh") $(printf '%q' "$out") \
  "\${1:?usage: run_task.sh N}"
EOF
chmod +x "$out/run_task.sh"

# The tasks to run: all, or those --only names; minus those whose row exists (--resume).
todo=() est=0
while IFS=$'\t' read -r i name _ _ _ _ e _; do
  [[ -z $only || $name =~ $only ]] || continue
  if [[ -f $out/rows/$name.json ]] && ! grep -q '"status": "skipped"' "$out/rows/$name.json"; then
    continue
  fi
  todo+=("$i")
  est=$((est + e))
done < <(tail -n +2 "$out/tasks.tsv")
[[ -n $only && ${#todo[@]} -eq 0 && $resume -eq 0 ]] &&
  die "--only '$only' matches no task of the $panel panel"
est_txt=$(printf '%d min %02d s' $((est / 60)) $((est % 60)))

if [[ -n $slurm ]]; then
  mkdir -p "$out/slurm" "$(dirname "$slurm")"
  {
    echo "#!/usr/bin/env bash"
    echo "#SBATCH --job-name=rasm-scoreboard-$panel"
    echo "#SBATCH --array=1-$n"
    echo "#SBATCH --cpus-per-task=$slurm_cpus"
    echo "#SBATCH --time=$slurm_time"
    echo "#SBATCH --mem=$slurm_mem"
    echo "#SBATCH --output=$out/slurm/%A_%a.out"
    for e in "${sbatch_extra[@]}"; do echo "#SBATCH $e"; done
    echo "# Generated by scripts/scoreboard.sh: task SLURM_ARRAY_TASK_ID of $out/tasks.tsv per"
    echo "# array element. Submit with: sbatch $slurm"
    echo "# Afterwards: scripts/scoreboard.sh --out $out --gather"
    echo "set -euo pipefail"
    echo "export OMP_NUM_THREADS=\${SLURM_CPUS_PER_TASK:-1} OMP_WAIT_POLICY=passive"
    echo "exec bash $(printf '%q' "$out/run_task.sh") \"\$SLURM_ARRAY_TASK_ID\""
  } >"$slurm"
  bash -n "$slurm"
  python3 "$ROOT/scripts/scoreboard/meta.py" start "$out" --panel "$panel" \
    --command "$command_line" --rasm "$RASM" --jobs "$n" --omp "slurm $slurm_cpus" \
    "${resume_arg[@]}"
  echo "scoreboard.sh: wrote the Slurm array job $slurm ($n tasks): sbatch $slurm, then" \
    "scripts/scoreboard.sh --out $out --gather"
  exit 0
fi
if [[ $dry -eq 1 ]]; then
  awk -F'\t' 'NR > 1 { printf "%3d  %-36s %-14s %-16s %5s s\n", $1, $2, $3, $4, $7 }' \
    "$out/tasks.tsv"
  echo "scoreboard.sh: dry run: $n tasks in $out/tasks.tsv, ${#todo[@]} to run, estimated" \
    "$est_txt on 2 free cores; bash $out/run_task.sh N runs task N"
  exit 0
fi

# ---- run ----------------------------------------------------------------------------------------
python3 "$ROOT/scripts/scoreboard/meta.py" start "$out" --panel "$panel" --command "$command_line" \
  --rasm "$RASM" --jobs "$jobs" --omp "$OMP_NUM_THREADS" "${resume_arg[@]}"
echo "scoreboard.sh: $panel panel, ${#todo[@]} of $n tasks to run in $out (estimated $est_txt on" \
  "2 free cores), $jobs at once, OMP_NUM_THREADS=$OMP_NUM_THREADS"
SCOREBOARD_T0=$(date +%s)
export SCOREBOARD_T0
interrupted=0
trap 'interrupted=1' INT TERM
if [[ ${#todo[@]} -gt 0 ]]; then
  if [[ $jobs -eq 1 ]]; then
    for i in "${todo[@]}"; do
      rc=0
      bash "$out/run_task.sh" "$i" || rc=$?
      [[ $rc -eq 130 || $interrupted -eq 1 ]] && { interrupted=1; break; }
      [[ $rc -eq 0 ]] || echo "scoreboard.sh: task $i: run_task.sh exited $rc" >&2
    done
  else
    # (a failed task still exits 0 with its row; Ctrl-C sets $interrupted through the trap)
    parallel --will-cite --jobs "$jobs" --line-buffer --halt never bash "$out/run_task.sh" {} \
      ::: "${todo[@]}" || true
  fi
fi
trap - INT TERM
wall=$(($(date +%s) - SCOREBOARD_T0))
python3 "$ROOT/scripts/scoreboard/meta.py" finish "$out" --wall-s "$wall"
if [[ $interrupted -eq 1 ]]; then
  echo "scoreboard.sh: interrupted after $((wall / 60)) min $((wall % 60)) s: the finished" \
    "rows are kept; the same command with --resume continues (the table below covers the rows" \
    "so far)" >&2
  docs_md="" docs_json=""  # a partial table never replaces docs/
fi
echo "scoreboard.sh: ran in $((wall / 60)) min $((wall % 60)) s"
gather
[[ $interrupted -eq 1 ]] && exit 130
# Exit 1 when a task failed (its row says why); skipped tasks (data absent) are not failures.
failed=$({ grep -l '"status": "failed"' "$out"/rows/*.json 2>/dev/null || true; } |
  xargs -r -n1 basename | sed 's/\.json$//' | tr '\n' ' ')
if [[ -n $failed ]]; then
  echo "scoreboard.sh: tasks failed: $failed(their logs: $out/runs/<task>.log)" >&2
  exit 1
fi
