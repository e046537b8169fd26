#!/usr/bin/env bash
# Evaluation sweeps that scale out: a grid of independent `rasm run`s, each with its own --out and
# --set overrides, listed in <out>/tasks.tsv and run by one generated command per task
# (<out>/run_task.sh N). Locally GNU parallel runs them; with --slurm the script writes a Slurm
# array job file instead (the same command, task SLURM_ARRAY_TASK_ID) and runs nothing. Then
# `rasm sweep gather <out>` makes the tables (results.md / .json / .csv, one row per task; for
# exploring runs also `rasm eval exploration`'s grouped table). docs/outputs.md "Sweeps".
#
#   scripts/sweep.sh [--out DIR] [--worlds "office two_rooms"] [--planners "ig frontier"]
#       [--seeds "1 2 3"] [--inputs "a.ini b.rawlog tum_folder"] [--jobs J] [--resume]
#       [--slurm FILE.sbatch [--slurm-time 01:00:00] [--slurm-cpus 2] [--slurm-mem 8G]
#        [--sbatch "--partition=x"]...] [--dry-run] [-- --set section.key=value ...]
#
# Grid (default): worlds x planners x seeds of exploring simulated runs (the world's robot spec,
# sim.seed and exploration.seed = the seed). --inputs instead: one task per INI file (rasm run
# file.ini) or rawlog / dataset folder ([source] type = auto), times --seeds when given (sim.seed,
# exploration.seed). Everything after -- goes to every task (e.g. --set source.max_frames=100).
# --jobs J: tasks at once (default: cores / 2, at least 1), each with OMP_NUM_THREADS = cores / J
# unless set. --resume: skip the tasks GNU parallel's joblog records as done. --dry-run: write the
# task list and run_task.sh only. RASM=path/to/rasm overrides the binary (default build/rasm).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
RASM=${RASM:-$ROOT/build/rasm}
out=sweep_out worlds=office planners=ig seeds="" inputs="" jobs="" resume=0 dry=0 gather=1
slurm="" slurm_time=01:00:00 slurm_cpus=2 slurm_mem=8G sbatch_extra=() extra=()
die() { echo "sweep.sh: $*" >&2; exit 2; }
need() { [[ $# -ge 2 ]] || die "$1 needs a value"; }
while [[ $# -gt 0 ]]; do
  case $1 in
    --out) need "$@"; out=$2; shift ;;
    --worlds) need "$@"; worlds=$2; shift ;;
    --planners) need "$@"; planners=$2; shift ;;
    --seeds) need "$@"; seeds=$2; shift ;;
    --inputs) need "$@"; inputs=$2; shift ;;
    --jobs) need "$@"; jobs=$2; shift ;;
    --resume) resume=1 ;;
    --dry-run) dry=1 ;;
    --no-gather) gather=0 ;;
    --slurm) need "$@"; slurm=$2; shift ;;
    --slurm-time) need "$@"; slurm_time=$2; shift ;;
    --slurm-cpus) need "$@"; slurm_cpus=$2; shift ;;
    --slurm-mem) need "$@"; slurm_mem=$2; shift ;;
    --sbatch) need "$@"; sbatch_extra+=("$2"); shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    *) die "unknown option '$1' (scripts/sweep.sh --help)" ;;
  esac
  shift
done
[[ -x $RASM ]] || die "no rasm binary at $RASM (scripts/build.sh, or set RASM)"
RASM=$(cd "$(dirname "$RASM")" && pwd)/$(basename "$RASM")
[[ -z $jobs ]] && jobs=$(( $(nproc) / 2 > 0 ? $(nproc) / 2 : 1 ))
[[ $jobs =~ ^[1-9][0-9]*$ ]] || die "--jobs '$jobs': expected a whole number >= 1"
mkdir -p "$out/runs"
out=$(cd "$out" && pwd)

robot_spec() {  # the robot trajectory spec an exploring run of a world starts from
  case $1 in
    office) echo office_robot_loop ;;
    cluttered_lab) echo cluttered_lab_robot ;;
    two_rooms) echo two_rooms_robot ;;
    *) echo "${1%.yaml}_robot.yaml" ;;
  esac
}

# ---- the task list: one line per task, the rasm run arguments shell-quoted (printf %q) -----------
tsv=$out/tasks.tsv
printf 'task\tname\tworld\tplanner\tseed\tinput\targs\n' >"$tsv"
n=0
add_task() {  # name world planner seed input -- rasm run arguments
  local name=$1 world=$2 planner=$3 seed=$4 input=$5
  shift 6
  n=$((n + 1))
  name=$(printf '%03d_%s' "$n" "$name")
  local q
  q=$(printf '%q ' "$@" --out "runs/$name" --set output.overwrite=true "${extra[@]}")
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$name" "$world" "$planner" "$seed" "$input" \
    "${q% }" >>"$tsv"
}
if [[ -n $inputs ]]; then
  for input in $inputs; do
    [[ -e $input ]] || die "--inputs: '$input' does not exist (expected an INI file, rawlog or folder)"
    abs=$(cd "$(dirname "$input")" && pwd)/$(basename "$input")
    base=$(basename "${input%.*}")
    if [[ $input == *.ini ]]; then src=("$abs"); else src=(--set source.type=auto --set "source.path=$abs"); fi
    if [[ -z $seeds ]]; then
      add_task "$base" "" "" "" "$abs" -- "${src[@]}"
    else
      for s in $seeds; do
        add_task "${base}_s$s" "" "" "$s" "$abs" -- "${src[@]}" --set "sim.seed=$s" \
          --set "exploration.seed=$s"
      done
    fi
  done
else
  for w in $worlds; do
    [[ $w == *.yaml ]] && w=$(cd "$(dirname "$w")" && pwd)/$(basename "$w")
    wname=$(basename "${w%.yaml}")
    for p in $planners; do
      for s in ${seeds:-1}; do
        add_task "${wname}_${p}_s$s" "$wname" "$p" "$s" "" -- --set "sim.world=$w" \
          --set "sim.trajectory=$(robot_spec "$w")" --set "sim.seed=$s" \
          --set "exploration.seed=$s" --set "exploration.planner=$p" --set exploration.enabled=true
      done
    done
  done
fi
[[ $n -gt 0 ]] || die "no task (empty --worlds / --planners / --inputs)"

# ---- the one command per task --------------------------------------------------------------------
cat >"$out/run_task.sh" <<EOF
#!/usr/bin/env bash
# Generated by scripts/sweep.sh: runs task N (1-based) of tasks.tsv in this folder, the same way
# under GNU parallel and under Slurm: rasm run <its args> --out runs/<name>, log runs/<name>.log.
set -euo pipefail
cd "\$(dirname "\$0")"
RASM=\${RASM:-$RASM}
n=\${1:?usage: run_task.sh <task number 1..$n>}
line=\$(awk -F'\\t' -v n="\$n" 'NR > 1 && \$1 == n' tasks.tsv)
[[ -n \$line ]] || { echo "run_task.sh: no task \$n in \$PWD/tasks.tsv" >&2; exit 2; }
name=\$(cut -f2 <<<"\$line")
eval "set -- \$(cut -f7 <<<"\$line")"
echo "task \$n (\$name): \$RASM run \$*" >"runs/\$name.log"
exec "\$RASM" run "\$@" >>"runs/\$name.log" 2>&1
EOF
chmod +x "$out/run_task.sh"
echo "sweep.sh: $n tasks in $tsv"

if [[ -n $slurm ]]; then
  mkdir -p "$out/slurm"
  {
    echo "#!/usr/bin/env bash"
    echo "#SBATCH --job-name=rasm-sweep"
    echo "#SBATCH --array=1-$n"
    echo "#SBATCH --cpus-per-task=$slurm_cpus"
    echo "#SBATCH --time=$slurm_time"
    echo "#SBATCH --mem=$slurm_mem"
    echo "#SBATCH --output=$out/slurm/%A_%a.out"
    for e in "${sbatch_extra[@]}"; do echo "#SBATCH $e"; done
    echo "# Generated by scripts/sweep.sh: task SLURM_ARRAY_TASK_ID of $tsv per array element."
    echo "# Submit with: sbatch $slurm   Afterwards: $RASM sweep gather $out"
    echo "set -euo pipefail"
    echo "export OMP_NUM_THREADS=\${SLURM_CPUS_PER_TASK:-1}"
    echo "exec bash $(printf '%q' "$out/run_task.sh") \"\$SLURM_ARRAY_TASK_ID\""
  } >"$slurm"
  bash -n "$slurm"
  echo "sweep.sh: wrote the Slurm array job $slurm (sbatch $slurm; then $RASM sweep gather $out)"
  exit 0
fi
[[ $dry -eq 1 ]] && { echo "sweep.sh: dry run: bash $out/run_task.sh N runs task N"; exit 0; }

command -v parallel >/dev/null || die "GNU parallel not found (scripts/install-deps.sh installs it)"
[[ -n ${OMP_NUM_THREADS:-} ]] || export OMP_NUM_THREADS=$(( $(nproc) / jobs > 0 ? $(nproc) / jobs : 1 ))
resume_args=()
[[ $resume -eq 1 ]] && resume_args=(--resume)
echo "sweep.sh: running $n tasks, $jobs at once (OMP_NUM_THREADS=$OMP_NUM_THREADS), joblog $out/joblog.tsv"
status=0
parallel --will-cite --jobs "$jobs" --joblog "$out/joblog.tsv" "${resume_args[@]}" --halt never \
  bash "$out/run_task.sh" {} ::: $(seq 1 "$n") || status=$?
[[ $status -eq 0 ]] || echo "sweep.sh: $status tasks failed (their logs: $out/runs/<name>.log)" >&2
[[ $gather -eq 1 ]] && "$RASM" sweep gather "$out"
exit "$status"
