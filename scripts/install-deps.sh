#!/usr/bin/env bash
# Installs every build and run dependency of rasm from Debian 12 packages, by name.
# Non-interactive, idempotent; works as root (CI) or through sudo. Downloads nothing else.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config git
  libmrpt-dev mrpt-apps mrpt-common         # MRPT 2.5: obs, maps, nav, kinematics, opengl, hwdrivers
  libmrpt-tclap-dev                          # MRPT's TCLAP: the command line of rasm (app/Options.h)
  libopencv-dev libopencv-contrib-dev        # image ops, DNN loading; ximgproc (Edge Boxes, IV-A)
  darknet                                    # /usr/share/darknet: yolov3.cfg, coco.names, dog.jpg (IV tests)
  libeigen3-dev liboctomap-dev libnanoflann-dev
  libembree-dev libassimp-dev                # simulator: ray casting, meshes
  nlohmann-json3-dev libyaml-cpp-dev         # JSON outputs, world files
  libopen3d-dev                              # mesh.ply: TSDF fusion and marching cubes (meshing/)
  zlib1g-dev                                 # io: a gzip rawlog is checked whole before its first frame
  libgtest-dev libgmock-dev googletest
  xvfb xauth netpbm x11-apps xdotool         # optional: screenshots of RawLogViewer / SceneViewer3D
  clang-format clang-tidy                    # scripts/format.sh, scripts/tidy.sh
  graphviz                                   # scripts/module-graph.sh: docs/images/modules.svg
  clang libclang-rt-14-dev libomp-14-dev     # scripts/fuzz.sh: libFuzzer + ASan/UBSan, OpenMP for clang
  parallel                                   # GNU parallel: scripts/sweep.sh runs a sweep's tasks locally
  python3                                    # scripts/scoreboard.sh: metrics and the results table
  python3-matplotlib                         # scripts/plots.py: publication plots of a run
)

SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps.sh: not root and no sudo" >&2; exit 1; }
  SUDO="sudo"
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps.sh: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
echo "install-deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
