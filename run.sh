#!/usr/bin/env bash
# funnel's main job: install what is missing, build in Release, and write the results to out/.
set -euo pipefail
cd "$(dirname "$0")"
source scripts/setup.sh
funnel_build build
mkdir -p out
start=$(date +%s)
# Until the full paper reproduction exists: the theta sweep of the paper's Figs. 3a-5a
# (e = 0.99, mu = 1, beta0 = 0, N = 4000, theta = 5..85 deg in 0.5 deg steps).
./build/funnel sweep --theta 5:85:0.5 --e 0.99 --mu 1 --beta0 0 --samples 4000 --out out/theta_sweep.csv
echo "funnel: wrote out/theta_sweep.csv in $(( $(date +%s) - start )) s"
