#!/usr/bin/env bash
# Sets up and builds FretSim, then runs the default scene — the paper's
# section 5 case, a 6208 deep groove ball bearing in its housing (builds the
# outer ring's reduced model on first use, about 2 minutes; the run two to
# three more) — and prints where the results and pictures went.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/fretsim run configs/paper_dgbb_housing.prm -o results/paper_dgbb_housing "$@"
