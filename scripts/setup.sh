#!/usr/bin/env bash
# Installs FretSim's Debian packages (only those missing), then configures and
# builds. Idempotent: fast when everything is already there.
#
#   scripts/setup.sh              # builds everything: program, tests, benchmarks
#   scripts/setup.sh fretsim      # builds only the named targets (here the program)
#
# Environment: FRETSIM_BUILD_DIR (default build), FRETSIM_BUILD_TYPE (default
# Release). When ccache is installed, a new build directory compiles through it
# (rebuilds after a clean or in a second clone then take seconds); it is not
# installed here, as it does not speed up a first build.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config
  libdeal.ii-dev libsundials-dev libeigen3-dev libfftw3-dev libcli11-dev libhdf5-openmpi-dev
  libgtest-dev libbenchmark-dev
  python3 python3-matplotlib python3-h5py
  # Optimised BLAS/LAPACK behind Debian's libblas.so.3 alternative: MUMPS's
  # factorisations (reduction, modes, direct solves) are ~9x faster than with
  # the reference BLAS. Serial, so that MPI ranks do not oversubscribe cores.
  libopenblas0-serial
)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
fi

build_dir="${FRETSIM_BUILD_DIR:-build}"
build_type="${FRETSIM_BUILD_TYPE:-Release}"
if [ ! -f "$build_dir/build.ninja" ]; then
  launcher=()
  if command -v ccache > /dev/null 2>&1; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  configure_log="$build_dir-configure.log"
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" "${launcher[@]}" \
    > "$configure_log" 2>&1 || { cat "$configure_log"; exit 1; }
  rm -f "$configure_log"
fi
targets=()
[ $# -eq 0 ] || targets=(--target "$@")
cmake --build "$build_dir" --parallel "$(nproc)" "${targets[@]}"
