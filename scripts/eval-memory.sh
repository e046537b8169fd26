#!/usr/bin/env bash
# Long-run memory check (issue 15, deliverable 6; docs/io.md "Memory on long runs"): the
# simulated robot drives office_robot_loop's loop LAPS times (default 24: ~10 simulated minutes)
# with the whole pipeline on (tracking, fusion, segmentation, classification; no exploration, so
# the path is the same every lap), then `rasm eval memory` reports surfels, RSS and map store at
# half time and at the end, their growth over the second half (target < 5%) and bytes per surfel,
# and plots the curves (memory.png).
#   scripts/eval-memory.sh [laps] [--set key=value ...]    (640x480 at 10 Hz by default)
set -euo pipefail
cd "$(dirname "$0")/.."
RASM=${RASM:-build/rasm}
OUT=${OUT:-eval_out/memory}
LAPS=${1:-24}
shift || true
[[ -x "$RASM" ]] || { echo "build first: scripts/build.sh" >&2; exit 1; }
mkdir -p "$OUT"
spec="$OUT/office_robot_laps.yaml"
{
  echo "# office_robot_loop's waypoints $LAPS times (scripts/eval-memory.sh)"
  echo "type: robot"
  echo "rate_hz: 10"
  echo "start: {x: 1.2, y: 2.5, yaw_deg: 0}"
  printf "waypoints: ["
  for ((i = 0; i < LAPS; ++i)); do
    [[ $i -gt 0 ]] && printf ", "
    printf "[4.3, 2.2], [4.3, 3.9], [1.5, 3.9], [1.2, 2.5]"
  done
  echo "]"
  echo "controller: {lookahead_m: 0.5, max_v_mps: 0.35, max_w_degps: 45}"
  echo "robot: {footprint_radius_m: 0.25, camera_height_m: 0.55, camera_pitch_deg: -10}"
} > "$spec"
run="$OUT/run"
"$RASM" run --out "$run" --set sim.world=office --set sim.trajectory="$spec" \
  --set explore.enabled=false --set output.write_ply=false --set output.write_3dscene=false \
  --set output.preview_png=false "$@"
"$RASM" eval memory "$run" --json "$OUT/memory.json" --plot "$OUT/memory.png"
