#!/usr/bin/env bash
# Sets up and builds FretSim, then runs the whole test suite under ctest.
# Extra arguments go to ctest, e.g. `-L unit` or `-LE slow`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd build
ctest --output-on-failure --timeout 1500 -j "$(nproc)" "$@"
