#!/usr/bin/env bash
# Reproduces the tracking accuracy and speed numbers of the surfel SLAM core (issue: Surfel SLAM
# core; results and analysis in docs/slam-eval.md): ATE RMSE with `rasm eval ate` (SE(3) and
# Sim(3) alignment), RPE over 1 s, frames/s, per-stage ms and peak memory on the real sequences
# in ../shared/data and on the 60 s simulated hand-held office sequence, and for the real ones
# also the frame rate of the mapping alone (frames decoded before the clock starts: rasm bench
# --preload). Prints one line per sequence and writes $OUT/summary.json (one object per line).
#   scripts/eval-slam.sh [--quick]      (--quick: real sequences only)
#   scripts/eval-slam.sh --tracking [eval-tracking.sh options]
# --tracking runs the robust-tracking evaluation of issue 14 instead (robot paths, fast pans,
# kidnapping, generated worlds, real data: scripts/eval-tracking.sh, which lists its options;
# none = all of it, hours on 2 cores).
# Frame rates depend on the machine and on what else runs on it; ATE does not.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--tracking" ]]; then shift; exec scripts/eval-tracking.sh "$@"; fi
RASM=${RASM:-build/rasm}
DATA=${RASM_SHARED_DATA:-../shared/data}
OUT=${OUT:-eval_out}
mkdir -p "$OUT"
[[ -x "$RASM" ]] || { echo "build first: scripts/build.sh" >&2; exit 1; }
rm -f "$OUT/summary.jsonl"

run_seq() {  # name ini [overrides...]
  local name=$1 ini=$2; shift 2
  local args=()
  for o in "$@"; do args+=(--set "$o"); done
  echo "running $name ($ini ${*:-}) ..." >&2
  "$RASM" run "$ini" --out "$OUT/$name" "${args[@]}" > "$OUT/$name.log" 2>&1 || { echo "$name: run failed (see $OUT/$name.log)"; return; }
  local gt="$OUT/$name/groundtruth.txt" est="$OUT/$name/trajectory.txt"
  "$RASM" eval ate "$gt" "$est" --json "$OUT/$name/ate.json" > "$OUT/$name/ate.txt"
  "$RASM" eval ate "$gt" "$est" --scale --json "$OUT/$name/ate_sim3.json" > "$OUT/$name/ate_sim3.txt"
  "$RASM" eval rpe "$gt" "$est" --json "$OUT/$name/rpe.json" > "$OUT/$name/rpe.txt"
  python3 - "$OUT/$name" "$name" "$OUT/summary.jsonl" <<'PY'
import json, sys
d, name, summary = sys.argv[1:4]
rep = json.load(open(d + "/report.json"))
def rmse(f):
    j = json.load(open(f))
    j = j.get("ate", j)
    return j["translation_m"]["rmse"]
rpe = json.load(open(d + "/rpe.json"))
st = {k: round(v["mean_ms"], 2) for k, v in rep["stages"].items()}
row = {"sequence": name, "frames": rep["frames"], "frames_lost": rep["frames_lost"],
       "ate_rmse_m": rmse(d + "/ate.json"), "ate_sim3_rmse_m": rmse(d + "/ate_sim3.json"),
       "rpe_1s_translation_rmse_m": rpe["translation_m"]["rmse"],
       "rpe_1s_rotation_rmse_deg": rpe["rotation_deg"]["rmse"],
       "fps": rep["fps"], "cpu_ms_per_frame": rep.get("cpu_ms_per_frame"),
       "stage_mean_ms": st, "surfels": rep.get("surfels"),
       "peak_rss_mb": rep.get("peak_rss_mb")}
if row["surfels"] and row["peak_rss_mb"]:
    row["peak_rss_mb_per_million_surfels"] = round(row["peak_rss_mb"] / (row["surfels"] / 1e6), 1)
open(summary, "a").write(json.dumps(row) + "\n")
print(f"{name:28s} frames {row['frames']:5d} lost {row['frames_lost']:3d}  ATE {100*row['ate_rmse_m']:.2f} cm "
      f"(Sim3 {100*row['ate_sim3_rmse_m']:.2f})  RPE/1s {100*row['rpe_1s_translation_rmse_m']:.2f} cm  "
      f"{row['fps']:.2f} frames/s ({row['cpu_ms_per_frame'] or 0:.0f} CPU ms/frame)  " + " ".join(f"{k} {v:.1f}" for k, v in st.items() if k != "total") +
      f" ms  peak {row['peak_rss_mb']:.0f} MB, {row['surfels']} surfels")
PY
}

bench_seq() {  # name ini [overrides...]: frame rate of the mapping alone (frames decoded first)
  local name=$1 ini=$2; shift 2
  local args=()
  for o in "$@"; do args+=(--set "$o"); done
  echo "benchmarking $name (rasm bench --preload) ..." >&2
  "$RASM" bench "$ini" --preload "${args[@]}" 2> "$OUT/$name.bench.log" > "$OUT/$name.bench.json" || { echo "$name: bench failed (see $OUT/$name.bench.log)"; return; }
  python3 - "$OUT/$name.bench.json" "$name" "$OUT/summary.jsonl" <<'PY'
import json, sys
f, name, summary = sys.argv[1:4]
rep = json.load(open(f))
st = {k: round(v["mean_ms"], 2) for k, v in rep["stages"].items()}
row = {"sequence": name, "bench": "mapping, frames preloaded", "frames": rep["frames"],
       "fps": rep["fps"], "cpu_ms_per_frame": rep.get("cpu_ms_per_frame"), "stage_mean_ms": st}
open(summary, "a").write(json.dumps(row) + "\n")
print(f"{name:28s} mapping alone (preloaded): {row['fps']:.2f} frames/s ({row['cpu_ms_per_frame'] or 0:.0f} CPU ms/frame)  " +
      " ".join(f"{k} {v:.1f}" for k, v in st.items() if k != "total") + " ms")
PY
}

if [[ -d "$DATA/tum/fr1_xyz_first37" ]]; then bench_seq tum_fr1_xyz_first37 ini/tum_fr1_xyz.ini "source.path=$DATA/tum/fr1_xyz_first37"; fi
if [[ -d "$DATA/7scenes/redkitchen_first300" ]]; then bench_seq 7scenes_redkitchen_first300 ini/7scenes_redkitchen.ini "source.path=$DATA/7scenes/redkitchen_first300"; fi
if [[ -d "$DATA/tum/fr1_xyz_first37" ]]; then run_seq tum_fr1_xyz_first37 ini/tum_fr1_xyz.ini "source.path=$DATA/tum/fr1_xyz_first37"; else echo "skipped TUM fr1_xyz_first37: $DATA/tum/fr1_xyz_first37 absent"; fi
if [[ -d "$DATA/7scenes/redkitchen_first300" ]]; then run_seq 7scenes_redkitchen_first300 ini/7scenes_redkitchen.ini "source.path=$DATA/7scenes/redkitchen_first300"; else echo "skipped 7-Scenes redkitchen_first300: absent"; fi
if [[ "${1:-}" != "--quick" ]]; then
  run_seq sim_office_handheld_long_60s ini/default.ini "sim.trajectory=office_handheld_long"
fi
python3 -c "import json,sys; rows=[json.loads(l) for l in open(sys.argv[1])]; json.dump(rows, open(sys.argv[2],'w'), indent=1)" "$OUT/summary.jsonl" "$OUT/summary.json"
echo "summary: $OUT/summary.json"
