#!/usr/bin/env bash
# Installs everything dwatch needs to build, test and benchmark, from Debian 12 packages only.
# Idempotent and non-interactive; works as root or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libgtest-dev libgmock-dev libbenchmark-dev   # tests and benchmarks
  libsimdjson-dev                              # reading traces
  nlohmann-json3-dev                           # writing JSON
  libcli11-dev                                 # the command line
  libedit-dev                                  # line editing at the session prompt
  libtomlplusplus-dev                          # scenario files
  libbullet-dev                                # the physics World
  liblua5.4-dev                                # host programs written by users in Lua 5.4
  libosmesa6-dev libglm-dev libpng-dev         # the 3D view: headless GL, matrices, PNG files
  libstb-dev                                   # stb_truetype: the view's text
  libavcodec-dev libavformat-dev libswscale-dev libavutil-dev  # videos: H.264 (x264) in MP4, VP9 (libvpx) in WebM
  libimgui-dev libglfw3-dev libgl-dev          # the debugger window: Dear ImGui 1.86, GLFW 3.3, OpenGL
  xvfb xauth libgl1-mesa-dri libglx-mesa0      # the window's tests: a real window under Xvfb (llvmpipe)
  fonts-dejavu-core                            # the view's labels and legend
  clang libclang-rt-14-dev                     # the fuzz targets and sanitizer builds
  clang-format                                 # scripts/check-format.sh (CI)
  time                                         # peak-memory figures for benchmarks (/usr/bin/time -v)
  file                                         # cpack -G DEB: its dependencies' search (dpkg-shlibdeps) runs it
  python3-matplotlib                           # bench paper's plots (scripts/plot_paper.py, /usr/bin/python3)
  pybind11-dev python3-dev python3-numpy       # the Python package (python/), for /usr/bin/python3
  python3-pytest                               # its tests (python/tests/, run by ctest)
  python3-build python3-venv python3-setuptools python3-wheel  # its wheel, built offline (python/pyproject.toml)
  python3-pandas python3-mypy                  # Matches.to_pandas(); the stubs' check (mypy.stubtest)
  jupyter-nbconvert python3-ipykernel          # the example notebook, executed by ctest (docs/examples/)
  libopenmpi-dev openmpi-bin                   # runs over several processes (mpirun -np N dwatch run, docs/design.md §12)
  libmetis-dev                                 # their --partition metis
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
