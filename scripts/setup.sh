#!/usr/bin/env bash
# hertzgear set-up: install the missing Debian packages, configure and build in Release, then
#   setup.sh run   -> run the main job: `hertzgear run` on the bundled paper scenes
#   setup.sh test  -> run the whole test suite (ctest, everything not labelled `long`)
#   setup.sh build -> stop after the build
# Idempotent: installs nothing and rebuilds nothing when nothing changed.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
mode="${1:-run}"
build_dir="${HERTZGEAR_BUILD_DIR:-build}"

packages=(
  g++ cmake make git pkg-config
  libdeal.ii-dev libgmsh-dev gmsh libeigen3-dev petsc-dev libmumps-dev libsundials-dev
  libopenblas0-pthread
  libopenmpi-dev openmpi-bin
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libfftw3-dev
  libboost-dev
  python3 python3-matplotlib python3-numpy python3-scipy
  chromium
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "[setup] installing missing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt_get=(apt-get)
  if [[ $(id -u) -ne 0 ]]; then apt_get=(sudo apt-get); fi
  "${apt_get[@]}" update -q
  "${apt_get[@]}" install -y -q --no-install-recommends "${missing[@]}"
else
  echo "[setup] all Debian packages present"
fi

# MPI refuses to run as root unless told; tests under mpirun need it.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1

if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
fi
jobs="$(nproc)"
cmake --build "$build_dir" -j "$jobs"

case "$mode" in
  build) ;;
  run)
    # Both paper pairs on the shipped FE stiffness tables: dynamics and report (hertzgear run
    # without a scene; a second call reuses the cached results).
    "$build_dir/app/hertzgear" run --out results/paper
    echo "[setup] open results/paper/paper_crowned/report/index.html" \
         "and results/paper/paper_uncrowned/report/index.html"
    ;;
  test)
    ctest --test-dir "$build_dir" -LE long --output-on-failure -j "$jobs" --timeout 900
    ;;
  *)
    echo "usage: scripts/setup.sh [run|test|build]" >&2
    exit 2
    ;;
esac
