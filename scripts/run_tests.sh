#!/usr/bin/env bash
# Sets up and builds FretSim (program, tests, benchmarks), then runs the whole
# test suite under ctest.
# Extra arguments go to ctest, e.g. `-L unit` or `-LE slow`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd "${FRETSIM_BUILD_DIR:-build}"
# Two tests at once, each with its OpenMP threads: spinning barriers would
# wait for the other test's threads (the flexible-housing test took 38 s
# alone and 1 052 s in the suite); passive waiting yields the core.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"
ctest --output-on-failure --timeout 1500 -j "$(nproc)" "$@"
