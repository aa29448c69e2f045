#!/usr/bin/env bash
# Installs everything ifem needs from Debian packages (idempotent; as root or through sudo),
# three.js from the npm registry (for `ifem view`'s page, into BUILD_DIR/web), then configures
# and builds Release in ./build on all cores.
#
#   scripts/setup.sh [--with-pcl | --no-pcl] [--no-build] [--build-dir DIR]
#
# --with-pcl   also install PCL (~400 packages, ~1 GiB installed) and build its optional adapter
#              (IFEM_WITH_PCL=1 does the same); by default the adapter is built only if PCL is
#              already installed (the core never needs PCL)
# --no-pcl     never build the PCL adapter, even if PCL is installed
# --no-build   install packages only
set -euo pipefail
cd "$(dirname "$0")/.."

with_pcl=auto
do_build=1
build_dir=build
while [ $# -gt 0 ]; do
  case "$1" in
    --with-pcl) with_pcl=1 ;;
    --no-pcl) with_pcl=0 ;;
    --no-build) do_build=0 ;;
    --build-dir) build_dir="$2"; shift ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "setup.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
[ "${IFEM_WITH_PCL:-0}" = 1 ] && with_pcl=1
[ "${IFEM_NO_PCL:-0}" = 1 ] && with_pcl=0

packages=(build-essential cmake libeigen3-dev libsuitesparse-dev libspectra-dev
          libnanoflann-dev libopenblas0-pthread libgtest-dev libgmock-dev libomp-dev
          zlib1g-dev                    # ifem render: the PNG's deflate stream
          libcli11-dev nlohmann-json3-dev  # the ifem command's options and its --json output
          clang-format-14 python3 git   # these three: the style checks (ctest -L style)
          clang libclang-rt-14-dev      # the fuzz build (scripts/fuzz.sh): libFuzzer runtime
          python3-dev python3-numpy python3-scipy python3-pybind11 pybind11-dev python3-pytest)
#         ^ the Python package (python/): built by default, tested by ctest with pytest
# OpenBLAS makes CHOLMOD's supernodal factorization 3–4× faster than reference BLAS (its pthread
# build: the serial one is not safe for our side-by-side factorizations, docs/decisions.md D-092).
# `ifem view`: npm fetches three.js (below); headless Chromium runs the page's tests
# (tests/cli/test_cli_view.py). Each only when its command is missing (a Node.js from elsewhere
# would conflict with Debian's npm).
command -v npm >/dev/null || packages+=(npm)
command -v chromium >/dev/null || packages+=(chromium)
if [ "$with_pcl" = 1 ] && [ -f pointcloud/pcl_adapter.cpp ]; then
  packages+=(libpcl-dev)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  if [ "$(id -u)" != 0 ]; then
    command -v sudo >/dev/null || { echo "setup.sh: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  echo "setup.sh: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "setup.sh: all packages present"
fi

# three.js for `ifem view` (the version the page is written for, solvers/recipes/view_scene.h),
# installed once; the page embeds it, so nothing of it is in the repository.
three_version=$(sed -n 's/.*kThreeVersion = "\(.*\)";/\1/p' solvers/recipes/view_scene.h)
three_json="$build_dir/web/node_modules/three/package.json"
if grep -q "\"version\": \"$three_version\"" "$three_json" 2>/dev/null; then
  echo "setup.sh: three.js $three_version present"
else
  echo "setup.sh: installing three.js $three_version (npm) into $build_dir/web"
  mkdir -p "$build_dir/web"
  npm install --prefix "$build_dir/web" --no-audit --no-fund --silent "three@$three_version"
fi

if [ "$do_build" = 1 ]; then
  # ON when PCL was asked for (a broken PCL install fails loudly), OFF with --no-pcl, else AUTO
  # (built when CMake finds PCL)
  pcl_option=AUTO
  [ "$with_pcl" = 1 ] && [ -f pointcloud/pcl_adapter.cpp ] && pcl_option=ON
  [ "$with_pcl" = 0 ] && pcl_option=OFF
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DIFEM_WITH_PCL="$pcl_option" >/dev/null
  cmake --build "$build_dir" -j"$(nproc)"
  # The Python package, where Debian's python3 finds it (/usr/local/lib/python3.X/dist-packages):
  # afterwards `python3 -c "import ifem"` works from any directory. Without root or sudo it stays
  # in the build tree: PYTHONPATH=$build_dir/python.
  if grep -q '^IFEM_BUILD_PYTHON:BOOL=ON' "$build_dir/CMakeCache.txt"; then
    if [ "$(id -u)" = 0 ]; then
      cmake --install "$build_dir" --component python >/dev/null
    elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
      sudo cmake --install "$build_dir" --component python >/dev/null
    else
      echo "setup.sh: not installing the Python package (no root): use PYTHONPATH=$build_dir/python"
    fi
  fi
fi
