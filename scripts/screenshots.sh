#!/usr/bin/env bash
# Screenshots of a run folder in MRPT's viewers, under a virtual X server (issue 19, 3-4):
#   viewer_sceneviewer3d.png   SceneViewer3D on map.3Dscene as it opens (the map, the paths, the
#                              last camera, the exploration's candidate views)
#   viewer_rawlogviewer.png    RawLogViewer on annotated.rawlog: the entries (odometry with the
#                              tracking status as label, scans, MAP_VIEW / CLASS_VIEW images), the
#                              travelled distance, the timeline per label (POSE_LOST rows)
#   viewer_rawlogviewer_path.png  its "Raw-map" > "Map from odometry": the estimated path
#   viewer_rasm_view.png       `rasm view <run> --png` (offscreen, CFBORender)
# PNGs are scaled to 800 pixels wide and reduced to 128 colours (small enough for docs/images).
#
# usage: scripts/screenshots.sh <run folder> [out folder (default docs/images)]
#   (a run with [output] write_rawlog = true, e.g. build/rasm run --set output.write_rawlog=true)
# Needs xvfb-run, xwd, netpbm, xdotool (scripts/install-deps.sh) and build/rasm (RASM=... to
# use another binary). The viewers' settings go to a temporary HOME; nothing of yours changes.
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ -z ${RASM_SHOTS_INSIDE:-} ]]; then
  [[ $# -ge 1 ]] || { sed -n '2,17p' "$0"; exit 2; }
  for t in xvfb-run xwd xwdtopnm pnmscale pnmquant pnmtopng xdotool SceneViewer3D RawLogViewer; do
    command -v "$t" >/dev/null || { echo "screenshots.sh: $t not found (scripts/install-deps.sh)" >&2; exit 2; }
  done
  run=$(realpath "$1")
  for f in map.3Dscene annotated.rawlog map.surfelmap trajectory.txt; do
    [[ -f $run/$f ]] || { echo "screenshots.sh: $run/$f not found (a run with [output] write_rawlog = true)" >&2; exit 2; }
  done
  out=$(realpath -m "${2:-docs/images}")
  mkdir -p "$out"
  home=$(mktemp -d)
  trap 'rm -rf "$home"' EXIT
  mkdir -p "$home/.RawLogViewer"
  printf '[tips]\nshow=false\n' >"$home/.RawLogViewer/config.cfg"
  RASM_SHOTS_INSIDE=1 HOME="$home" xvfb-run -a -s "-screen 0 1280x900x24" "$0" "$run" "$out"
  exit
fi

run=$1 out=$2
rasm=${RASM:-build/rasm}

# png <out.png> [xwd args...]: the screen (or a window) as a small PNG.
png() {
  local dst=$1
  shift
  xwd -silent "$@" | xwdtopnm 2>/dev/null | pnmscale -width 800 2>/dev/null |
    pnmquant 128 2>/dev/null | pnmtopng >"$dst"
  echo "screenshots.sh: wrote $dst"
}
# window <name pattern>: the id of the first visible window whose name matches (60 s at most).
window() {
  local id
  for _ in $(seq 120); do
    id=$(xdotool search --onlyvisible --name "$1" 2>/dev/null | head -1) || true
    [[ -n $id ]] && { echo "$id"; return; }
    sleep 0.5
  done
  echo "screenshots.sh: no window '$1' appeared within 60 s" >&2
  return 1
}

SceneViewer3D "$run/map.3Dscene" >/dev/null 2>&1 &
pid=$!
id=$(window "SceneViewer3D")
xdotool windowmove "$id" 0 0 windowsize "$id" 1280 900
sleep 6
png "$out/viewer_sceneviewer3d.png" -root
kill "$pid"

RawLogViewer "$run/annotated.rawlog" >/dev/null 2>&1 &
pid=$!
id=$(window "RawlogViewer")
xdotool windowmove "$id" 0 0 windowsize "$id" 1280 900
sleep 10  # loading (about 5 s for 400 frames at 320x240)
png "$out/viewer_rawlogviewer.png" -root
xdotool mousemove 227 60 click 1  # the toolbar's "Raw-map..." at this window size
id=$(window "raw map")
xdotool windowmove "$id" 0 0 windowsize "$id" 1200 850
sleep 2
xdotool mousemove --window "$id" 134 191 click 1  # "Map from odometry"
sleep 25
png "$out/viewer_rawlogviewer_path.png" -id "$id"
kill "$pid"

env -u DISPLAY "$rasm" view "$run" --png "$out/viewer_rasm_view.png" --size 800x600
