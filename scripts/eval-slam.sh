#!/usr/bin/env bash
# Reproduces the tracking accuracy and speed numbers of the surfel SLAM core (issue: Surfel SLAM
# core): ATE RMSE with `rasm eval ate` and frames/s on the real sequences in ../shared/data and on
# simulated hand-held sequences. Prints one line per sequence and writes eval_out/summary.json.
#   scripts/eval-slam.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
RASM=${RASM:-build/rasm}
DATA=${RASM_SHARED_DATA:-../shared/data}
OUT=${OUT:-eval_out}
mkdir -p "$OUT"
[[ -x "$RASM" ]] || { echo "build first: scripts/build.sh" >&2; exit 1; }

declare -a rows=()
run_seq() {  # name ini [overrides...]
  local name=$1 ini=$2; shift 2
  local args=()
  for o in "$@"; do args+=(--set "$o"); done
  "$RASM" run "$ini" --out "$OUT/$name" "${args[@]}" > "$OUT/$name.log" 2>&1 || { echo "$name: run failed (see $OUT/$name.log)"; return; }
  "$RASM" eval ate "$OUT/$name/groundtruth.txt" "$OUT/$name/trajectory.txt" --json "$OUT/$name/ate.json" > "$OUT/$name/ate.txt"
  python3 - "$OUT/$name" "$name" <<'PY'
import json, sys
d, name = sys.argv[1], sys.argv[2]
rep = json.load(open(d + "/report.json")); ate = json.load(open(d + "/ate.json"))
rmse = ate.get("ate", ate).get("translation_m", ate.get("translation_m", {})).get("rmse") if isinstance(ate, dict) else None
print(f"{name:28s} frames {rep['frames']:5d} lost {rep['frames_lost']:3d}  ATE RMSE {100*rmse:.2f} cm  {rep['fps']:.2f} frames/s  "
      f"track {rep['stages']['track']['mean_ms']:.1f} ms  fuse {rep['stages']['fuse']['mean_ms']:.1f} ms")
PY
}

if [[ -d "$DATA/tum/fr1_xyz_first37" ]]; then run_seq tum_fr1_xyz_first37 ini/tum_fr1_xyz.ini "source.path=$DATA/tum/fr1_xyz_first37"; fi
if [[ -d "$DATA/7scenes/redkitchen_first300" ]]; then run_seq 7scenes_redkitchen_first300 ini/7scenes_redkitchen.ini "source.path=$DATA/7scenes/redkitchen_first300"; fi
if [[ "${1:-}" != "--quick" ]]; then
  run_seq sim_office_handheld_long_60s ini/default.ini "sim.trajectory=office_handheld_long"
fi
