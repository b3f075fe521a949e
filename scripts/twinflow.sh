#!/usr/bin/env bash
# One-stop set-up for Twinflow on a fresh Debian machine (run as root, or with sudo available):
#   scripts/twinflow.sh run    install what is missing, build (Release, ccache), run the default scene
#   scripts/twinflow.sh test   install what is missing, build, run the quick test suite (ctest -L quick)
# Both are idempotent: nothing is installed or rebuilt when nothing changed.
set -euo pipefail
mode=${1:-run}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

packages=(cmake make g++ ccache libdeal.ii-dev libeigen3-dev libboost-dev libgtest-dev
          openmpi-bin python3-matplotlib
          libopenblas0-serial)  # optimised BLAS for Epetra's dot products and norms (the Krylov solves), one thread
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "twinflow: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.ccache}
jobs=$(nproc)
[ -f build/CMakeCache.txt ] || cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"

case "$mode" in
  run)
    scene=${2:-parameters/default.prm}
    ./build/twinflow "$scene"
    ;;
  test)
    cd build && ctest -L quick --output-on-failure -j"$jobs"   # tests declare PROCESSORS: -jN never oversubscribes
    ;;
  *)
    echo "usage: scripts/twinflow.sh run [SCENE.prm] | test" >&2
    exit 1
    ;;
esac
