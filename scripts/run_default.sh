#!/usr/bin/env bash
# Sets up and builds FretSim, then runs the default scene (the paper's
# concentrated contact) and prints where the results and pictures went.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/fretsim run configs/paper_concentrated.prm -o results/paper_concentrated "$@"
