#!/usr/bin/env bash
# Regenerates golden_trajectories.csv: per-trajectory outputs of a fixed set of release points,
# written in shortest round-trip form. test_golden.cpp requires every later build to reproduce
# them (to 1e-12 relative), so that optimisations cannot change results. Regenerate only for a
# deliberate change of the physics, and say so in the commit.
set -euo pipefail
bin=${1:-build/funnel}
out=$(dirname "$0")/golden_trajectories.csv
tmp=$(mktemp)
first=1
while read -r args; do
  [ -z "$args" ] && continue
  # shellcheck disable=SC2086
  "$bin" trajectory $args --format csv > "$tmp.row"
  if [ $first = 1 ]; then head -1 "$tmp.row" > "$tmp"; first=0; fi
  tail -1 "$tmp.row" >> "$tmp"
done <<'CASES'
--theta 60 --release 0.3
--theta 60 --release -0.777
--theta 46 --release 0.1
--theta 44 --release 0.1
--theta 20 --release 0.9
--theta 10 --release -0.35
--theta 85 --release 0.5
--theta 50 --e 0.95 --mu 0.3 --beta0 0.2 --release 0.37
--theta 25 --e 0.9 --mu 0.5 --beta0 -0.31 --release -0.61
--theta 70 --e 0.99 --mu 1 --beta0 0.31 --release 0.05
--theta 35 --e 0.3 --mu 0.2 --release 0.8
--theta 15 --e 0.8 --mu 2 --beta0 0.5 --radius 0.03 --gap 0.1 --release -0.2
--theta 40 --e 0 --mu 1 --release 0.5
--theta 75 --e 0.1 --mu 0.05 --release -0.45
--theta 30 --e 0.99 --mu 0 --release 0.23
--theta 55 --e 0.9 --mu 5 --beta0 -0.31 --inertia 0.6667 --release 0.91
--theta 45 --e 0.99 --mu 1 --release -0.5
--theta 60 --e 0.7 --mu 1 --gap 0 --release 0.4
--theta 50 --e 1 --mu 0.1 --gap 0 --max-collisions 5000 --release 0.3
--theta 30 --e 1 --mu 0 --gap 0 --t-max 200 --release -0.6
CASES
mv "$tmp" "$out"
rm -f "$tmp.row"
echo "wrote $out ($(($(wc -l < "$out") - 1)) cases)"
