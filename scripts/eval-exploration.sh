#!/usr/bin/env bash
# Exploration evaluation of issue 18 (results in docs/exploration.md "Results"): exploring
# `rasm run`s (the embedded default: [explore] enabled) over worlds x planners x seeds, then
# `rasm eval exploration` over their folders: a Markdown table (coverage and objects correctly
# classified at fixed simulated times, time to 90% coverage, path, why each run stopped), JSON and
# a coverage-against-time plot per world.
#   scripts/eval-exploration.sh [--worlds "office cluttered_lab two_rooms"] [--generated N]
#       [--planners "ig frontier random lawnmower"] [--seeds "1 2 3"] [--budget S] [--small]
#       [--poses tracked|groundtruth] [--jobs J] [-- --set section.key=value ...]
# --poses groundtruth fuses at the simulator's true poses: it compares the planners without the
# tracker's drift (which moves covered surface by more than the 2 cm of the coverage test);
# tracked (default) is the mission's own loop.
# --generated N adds rooms of `rasm sim generate --seed s` (s = 101..100+N) nobody tuned on.
# --small: 320x240 camera (faster; coverage is measured the same way). --jobs J runs J runs at
# once (xargs -P; each run uses the machine's cores, so J > 1 only pays on a bigger machine or
# when runs wait on each other). Existing run folders with
# an exploration.json are reused (delete $OUT to start over).
set -euo pipefail
cd "$(dirname "$0")/.."
RASM=${RASM:-build/rasm}
OUT=${OUT:-eval_out/exploration}
[[ -x "$RASM" ]] || { echo "build first: scripts/build.sh" >&2; exit 1; }
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
worlds="office cluttered_lab two_rooms" generated=0 planners="ig frontier random lawnmower"
seeds="1 2 3" budget=180 small=0 jobs=1 poses=tracked extra=()
while [[ $# -gt 0 ]]; do
  case $1 in
    --worlds) worlds=$2; shift ;;
    --generated) generated=$2; shift ;;
    --planners) planners=$2; shift ;;
    --seeds) seeds=$2; shift ;;
    --budget) budget=$2; shift ;;
    --small) small=1 ;;
    --poses) poses=$2; shift ;;
    --jobs) jobs=$2; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
small_args=""
[[ $small -eq 1 ]] && small_args="--set camera.preset= --set camera.width=320 --set camera.height=240 --set camera.fx=262.5 --set camera.fy=262.5 --set camera.cx=159.5 --set camera.cy=119.5"

robot_spec() {  # the robot spec whose start pose a world's exploring run uses
  case $1 in
    office) echo office_robot_loop ;;
    cluttered_lab) echo cluttered_lab_robot ;;
    two_rooms) echo two_rooms_robot ;;
    *) echo "${1%.yaml}_robot.yaml" ;;
  esac
}
all_worlds=($worlds)
for ((g = 0; g < generated; ++g)); do
  s=$((101 + g))
  w="$OUT/worlds/gen$s.yaml"
  [[ -f $w ]] || "$RASM" sim generate "$w" --seed "$s" >/dev/null
  all_worlds+=("$w")
done

cmds="$OUT/commands.txt"
: >"$cmds"
dirs=()
for w in "${all_worlds[@]}"; do
  name=$(basename "${w%.yaml}")
  for p in $planners; do
    for s in $seeds; do
      d="$OUT/runs/${name}_${p}_s${s}_$poses"
      dirs+=("$d")
      [[ -f $d/exploration.json ]] && continue
      echo "$RASM run --out $d --set output.overwrite=true --set sim.world=$w --set sim.trajectory=$(robot_spec "$w") --set sim.seed=$s --set exploration.seed=$s --set exploration.planner=$p --set explore.enabled=true --set explore.time_budget_s=$budget --set mapper.poses=$poses --set output.write_rawlog=false $small_args ${extra[*]:-} > $d.log 2>&1 || echo FAILED $d" >>"$cmds"
    done
  done
done
mkdir -p "$OUT/runs"
echo "$(wc -l <"$cmds") runs to do ($OUT/commands.txt)"
if [[ $jobs -gt 1 ]]; then
  tr '\n' '\0' <"$cmds" | xargs -0 -P "$jobs" -n 1 bash -c
else
  while read -r c; do echo "$c" | cut -c1-160; bash -c "$c"; done <"$cmds"
fi
for d in "${dirs[@]}"; do [[ -f $d/exploration.json ]] || echo "missing: $d (see $d.log)"; done
# The table covers every finished run under $OUT/runs (earlier calls with other options too).
ok=()
for d in "$OUT"/runs/*/; do [[ -f $d/exploration.json ]] && ok+=("${d%/}"); done
"$RASM" eval exploration "${ok[@]}" --times 60,120,180 --json "$OUT/exploration.json" \
  --markdown "$OUT/exploration.md" --plot "$OUT/exploration_coverage.png"
