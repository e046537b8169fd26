#!/bin/bash
# rasm run --view under Xvfb: the live window appears while the run maps, shows the map (the
# window grabbed with xwd is not blank: a window that drew nothing is one flat colour), and the
# run ends normally. Skipped (77) without xvfb-run / xwd / xdotool / netpbm / Debian's python3
# with matplotlib. Usage: test_live_view.sh RASM_BINARY
set -uo pipefail
rasm=$1
for t in xvfb-run xwd xdotool xwdtopnm pnmtopng; do
  command -v "$t" >/dev/null || { echo "skipped: $t not found (scripts/install-deps.sh)"; exit 77; }
done
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || { echo "skipped: no python3-matplotlib"; exit 77; }
if [[ -z ${RASM_VIEW_INSIDE:-} ]]; then
  # Without a display the run is refused before it starts, naming the key.
  headless=$(mktemp -d)
  if env -u DISPLAY "$rasm" run --view --max-frames 1 --out "$headless/run" >"$headless/out" 2>&1; then
    echo "FAIL: rasm run --view ran without a display"; rm -rf "$headless"; exit 1
  fi
  grep -q "\[view\] enabled" "$headless/out" || {
    echo "FAIL: the headless refusal does not name [view] enabled:"; cat "$headless/out"; rm -rf "$headless"; exit 1; }
  rm -rf "$headless"

  RASM_VIEW_INSIDE=1 exec xvfb-run -a -s "-screen 0 1280x1024x24" "$0" "$@"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The office robot loop at 320x240, 300 frames: long enough for several snapshots.
"$rasm" run --view --max-frames 300 --out "$work/run" --set view.period_s=0.2 \
  --set camera.preset= --set camera.width=320 --set camera.height=240 --set camera.fx=262.5 \
  --set camera.fy=262.5 --set camera.cx=159.5 --set camera.cy=119.5 \
  --set output.write_ply=false --set output.write_3dscene=false >"$work/run.out" 2>&1 &
pid=$!
id=
for _ in $(seq 120); do
  id=$(xdotool search --onlyvisible --name "rasm run: live view" 2>/dev/null | head -1)
  [[ -n $id ]] && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.25
done
[[ -n $id ]] || { echo "FAIL: no live view window appeared"; cat "$work/run.out"; exit 1; }
# Grab the window every quarter second for 4 s (a few snapshots drawn), keeping the last grab:
# on a fast machine the run may end, and its window close, before the 4 s are over.
grabbed=0
for _ in $(seq 16); do
  sleep 0.25
  if xwd -silent -id "$id" 2>/dev/null | xwdtopnm 2>/dev/null | pnmtopng >"$work/next.png" 2>/dev/null &&
    [[ -s $work/next.png ]]; then
    mv "$work/next.png" "$work/window.png"
    grabbed=1
  fi
  kill -0 $pid 2>/dev/null || break
done
[[ $grabbed -eq 1 ]] || { echo "FAIL: could not grab the window"; exit 1; }
wait $pid
rc=$?
[[ $rc -eq 0 ]] || { echo "FAIL: rasm run --view exited with $rc"; cat "$work/run.out"; exit 1; }
# What the last snapshot drew (run.log): the exploring run's plan (candidate views) and goals
# over the map; the objects drawn are counted (none may be confirmed yet after 300 frames).
drawn=$(grep -o "live view: .*" "$work/run/run.log" | tail -1)
echo "$drawn"
[[ $drawn =~ ([0-9]+)\ surfels,\ ([0-9]+)\ views\ \(([0-9]+)\ goals\),\ ([0-9]+)\ objects ]] || {
  echo "FAIL: run.log does not say what the live view drew"; exit 1; }
(( BASH_REMATCH[1] > 1000 )) || { echo "FAIL: the live view drew no map"; exit 1; }
(( BASH_REMATCH[2] > BASH_REMATCH[3] && BASH_REMATCH[3] >= 1 )) || {
  echo "FAIL: the live view drew no candidate views or no goal of the exploring run"; exit 1; }
/usr/bin/python3 - "$work/window.png" <<'PY' || exit 1
import sys
import matplotlib.image as mpimg
im = mpimg.imread(sys.argv[1])[:, :, :3]
std = float(im.std())
# Distinct colours in a coarse quantisation: the grid, the map's surfels, the path, the frustum.
levels = {tuple((p * 7).astype(int)) for p in im.reshape(-1, 3)[::97]}
print(f"window {im.shape[1]}x{im.shape[0]}: pixel std {std:.3f}, {len(levels)} colour levels")
if std < 0.03 or len(levels) < 8:
    print("FAIL: the live view window is blank")
    sys.exit(1)
PY
echo "ok: the live view showed the map"
