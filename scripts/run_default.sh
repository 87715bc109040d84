#!/usr/bin/env bash
# Sets up and builds the program (only the fretsim target: not the tests and
# benchmarks), then runs the default scene — the paper's section 5 case, a 6208
# deep groove ball bearing in its housing (builds the outer ring's reduced
# model and its stress tables on first use, about 2 minutes each; the run
# about one more) — and prints
# where the results and pictures went. Extra arguments go to `fretsim run`.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${FRETSIM_BUILD_DIR:-build}"
scripts/setup.sh fretsim
# --force: this command's own folder, replaced on every run (only the files a run writes).
"$build_dir/fretsim" run configs/paper_dgbb_housing.prm -o results/paper_dgbb_housing --force "$@"
