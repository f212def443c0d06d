#!/usr/bin/env bash
# Regenerates golden_trajectories.csv: per-trajectory outputs of a fixed set of release points,
# written in shortest round-trip form. test_golden.cpp requires every later build to reproduce
# them (to 1e-12 relative), so that optimisations cannot change results. Regenerate only for a
# deliberate change of the physics, and say so in the commit.
set -euo pipefail
bin=${1:-build/funnel}
out=$(dirname "$0")/golden_trajectories.csv
tmp=$(mktemp)
# record FILE [ARGS...]: one row per line of standard input (`funnel trajectory ARGS LINE`), under
# the header of the first, written to FILE.
record() {
  local file=$1 first=1 args
  shift
  while read -r args; do
    [ -z "$args" ] && continue
    # shellcheck disable=SC2086
    "$bin" trajectory "$@" $args --format csv > "$tmp.row"
    if [ $first = 1 ]; then head -1 "$tmp.row" > "$tmp"; first=0; fi
    tail -1 "$tmp.row" >> "$tmp"
  done
  mv "$tmp" "$file"
}
record "$out" <<'CASES'
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

# The 3D engine (--space 3d): golden_3d.csv, the same way. Off-plane releases whose contacts on the
# cone's face and on the rim are integrated (sliding, rolling, a hundred face-rim hand-overs, a
# periodic end extrapolated to the time cap), and flights with rim collisions; the last four are
# samples of fig3d's ensembles (θ = 44° and 60°, σ = 0.03 and 0.1) whose results move when an
# event is scanned with the wrong frame. test_golden.cpp requires them to 1e-10 relative.
out3=$(dirname "$0")/golden_3d.csv
record "$out3" --space 3d <<'CASES'
--theta 60 --release 0.7 --release-u 0.02 --release-w 0.03 --t-max 100
--theta 60 --release 0.95 --release-u 0.1 --release-w 0.1 --t-max 100
--theta 50 --release 0.99 --release-u 0.05 --release-w 0.05 --t-max 300
--theta 44 --release 0.99 --release-u 0.01 --release-w 0.05 --t-max 300
--theta 46 --release 0.7 --release-u 0.1 --release-w 0.1 --t-max 100
--theta 44 --release 0.3 --release-u 0.1 --release-w 0.03 --t-max 100
--theta 60 --release 0.8 --release-w 0.05 --mu 0.3 --beta0 0.31 --t-max 100
--theta 55 --release 0.6 --release-u -0.03 --release-w 0.04 --release-spin-y 2 --release-spin-x -1 --t-max 100
--theta 44 --release 0.9764092379735047 --release-u 0.02657927840518672 --release-w 0.014015796220603815 --t-max 300
--theta 44 --release 0.8982622111610841 --release-u -0.12452898506654436 --release-w -0.25902570191062924 --t-max 300
--theta 60 --release 0.9135781302110947 --release-u -0.014701653516740664 --release-w 0.02945866742283339 --t-max 300
--theta 60 --release 0.8435786863120712 --release-u -0.05312964270381368 --release-w -0.11207927886186389 --t-max 300
CASES
rm -f "$tmp.row"
echo "wrote $out ($(($(wc -l < "$out") - 1)) cases)"
