#!/usr/bin/env bash
# Classification evaluation of issue 17 (results in docs/classification.md "Results"). Runs
# `rasm run` on simulated sequences with the simulated detector (the embedded default's
# [classification]), then `rasm eval classification <run> --json <run>/classification.json`, and
# prints one line per sequence: objects evaluated, object accuracy, segmented COCO-class accuracy
# (the issue's target), macro precision, detections fused / total. Writes $OUT/classification.jsonl
# and a markdown table at the end.
#   scripts/eval-classification.sh [--shipped] [--worlds N] [--first-seed S] [--small]
#                                  [--max-frames N] [-- --set section.key=value ...]
# --shipped: office + office_handheld, office + office_robot_loop, cluttered_lab +
#   cluttered_lab_handheld. --worlds N: rooms of `rasm sim generate --seed s` (s = S..S+N-1),
#   each with its _handheld and _robot trajectory. --small: 320x240 for every sequence.
# Arguments after -- go to every `rasm run` (e.g. -- --set classification.min_iou=0.15).
# Existing run folders with a classification.json are reused (delete $OUT to start over).
set -euo pipefail
cd "$(dirname "$0")/.."
RASM=${RASM:-build/rasm}
OUT=${OUT:-eval_out/classification}
[[ -x "$RASM" ]] || { echo "build first: scripts/build.sh" >&2; exit 1; }
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
shipped=0 worlds=0 first_seed=1 small=0 max_frames=0 extra=()
if [[ $# -eq 0 ]]; then shipped=1 worlds=3; fi
while [[ $# -gt 0 ]]; do
  case $1 in
    --shipped) shipped=1 ;;
    --worlds) worlds=$2; shift ;;
    --first-seed) first_seed=$2; shift ;;
    --small) small=1 ;;
    --max-frames) max_frames=$2; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
small_args=()
[[ $small -eq 1 ]] && small_args=(--set camera.width=320 --set camera.height=240 --set camera.fx=262.5
                                  --set camera.fy=262.5 --set camera.cx=159.5 --set camera.cy=119.5)
JL="$OUT/classification.jsonl"

evaluate() {  # name world trajectory seed
  local name=$1 world=$2 traj=$3 seed=$4
  local out="$OUT/$name"
  if [[ ! -f "$out/classification.json" ]]; then
    rm -rf "$out"
    "$RASM" run --out "$out" --set source.type=sim --set sim.world="$world" --set sim.trajectory="$traj" \
      --set sim.seed="$seed" --set source.max_frames="$max_frames" \
      --set output.write_3dscene=false --set output.save_map=false --set output.write_ply=true \
      "${small_args[@]}" "${extra[@]}" > "$out.log" 2>&1 || { echo "$name: run failed (see $out.log)"; return; }
    "$RASM" eval classification "$out" --json "$out/classification.json" > "$out/classification.txt" 2>&1 ||
      { echo "$name: eval failed (see $out/classification.txt)"; return; }
  fi
  python3 - "$out" "$name" "$JL" <<'PY'
import json, math, sys
d, name, jl = sys.argv[1:4]
rep = json.load(open(d + "/report.json"))
ev = json.load(open(d + "/classification.json"))
cl = rep.get("classification", {})
precs = [c["precision"] for c in ev["per_class"].values() if c.get("precision") is not None]
row = {"sequence": name, "frames": rep["frames"], "tracked_fraction": rep.get("tracked_fraction"),
       "objects_evaluated": ev["objects_evaluated"], "object_accuracy": ev["object_accuracy"],
       "segmented_coco_objects": ev["segmented_coco_objects"],
       "segmented_coco_accuracy": ev["segmented_coco_accuracy"],
       "macro_precision": sum(precs) / len(precs) if precs else None,
       "detections": cl.get("detections"), "detections_fused": cl.get("detections_fused")}
open(jl, "a").write(json.dumps(row) + "\n")
f = lambda x, p=3: "n/a" if x is None else f"{x:.{p}f}"
print(f"{name:26s} frames {row['frames']:4d}  objects {row['objects_evaluated']:3d}  accuracy {f(row['object_accuracy'])}  "
      f"segmented COCO {f(row['segmented_coco_accuracy'])} of {row['segmented_coco_objects']}  "
      f"macro precision {f(row['macro_precision'])}  detections fused {row['detections_fused']}/{row['detections']}", flush=True)
PY
}

rm -f "$JL"
if [[ $shipped -eq 1 ]]; then
  evaluate office_handheld office office_handheld 1
  evaluate office_robot_loop office office_robot_loop 1
  evaluate cluttered_lab_handheld cluttered_lab cluttered_lab_handheld 1
fi
for ((s = first_seed; s < first_seed + worlds; ++s)); do
  w="$OUT/gen_s$s.yaml"
  [[ -f "$w" ]] || "$RASM" sim generate "$w" --seed "$s" > "$OUT/gen_s$s.log" 2>&1 ||
    { echo "gen_s$s: generate failed (see $OUT/gen_s$s.log)"; continue; }
  for t in handheld robot; do evaluate "gen_s${s}_$t" "$w" "$OUT/gen_s${s}_$t.yaml" "$s"; done
done
[[ -s "$JL" ]] || exit 0
python3 - "$JL" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
f = lambda x, p=3: "n/a" if x is None else f"{x:.{p}f}"
print("\n| sequence | frames | objects | object accuracy | segmented COCO-class accuracy | macro precision | detections fused |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    print(f"| {r['sequence']} | {r['frames']} | {r['objects_evaluated']} | {f(r['object_accuracy'])} | "
          f"{f(r['segmented_coco_accuracy'])} ({r['segmented_coco_objects']}) | {f(r['macro_precision'])} | "
          f"{r['detections_fused']}/{r['detections']} |")
PY
