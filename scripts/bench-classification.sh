#!/usr/bin/env bash
# Speed of the full semantic loop of issue 17 (deliverable 7): tracking, fusion, segmentation,
# the default DNN detector for real data (NanoDet-m; --set dnn_detector.preset=yolo_fastest for
# Yolo-Fastest) every 5th fused frame and the zero-shot classifier (office bank) on worker threads,
# on 7-Scenes redkitchen (300 frames, preloaded so decoding is not timed). Prints the frame rate,
# CPU ms per frame, per-stage means and each detector's ms per call and skipped frames, then the
# same without classification for comparison. Run it on a quiet machine: it measures wall time.
#   scripts/bench-classification.sh [extra rasm bench args, e.g. --set classification.every_n_frames=10]
set -euo pipefail
cd "$(dirname "$0")/.."
RASM=${RASM:-build/rasm}
[[ -x "$RASM" ]] || { echo "build first: scripts/build.sh" >&2; exit 1; }
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
BANK=${BANK:-/tmp/rasm_office_zero_shot.bank}
run() {  # label, then rasm bench args
  local label=$1; shift
  "$RASM" bench ini/7scenes_redkitchen.ini --preload "$@" 2>/dev/null | python3 -c "
import json, sys
r = json.loads(sys.stdin.read().strip().splitlines()[-1])
st = r.get('stages', {})
ms = lambda k: st.get(k, {}).get('mean_ms')
out = {'bench': '$label', 'frames': r.get('frames'), 'fps': r.get('fps'),
       'cpu_ms_per_frame': r.get('cpu_ms_per_frame'),
       'stage_mean_ms': {k: ms(k) for k in ('preprocess', 'tracking', 'index_map', 'segmentation', 'fuse', 'classification', 'total')}}
c = r.get('classification', {})
out['detectors'] = [{k: d.get(k) for k in ('name', 'frames_offered', 'frames_detected', 'frames_skipped', 'detections', 'ms_per_call', 'ms_max')} for d in c.get('detectors', [])]
print(json.dumps(out))
"
}
run semantic_loop --set classification.detectors=dnn_detector,zero_shot --set zero_shot.enabled=true \
  --set zero_shot.models=office_zero_shot --set zero_shot.bank="$BANK" "$@"
run no_classification --set classification.enabled=false "$@"
