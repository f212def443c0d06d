#!/usr/bin/env bash
# funnel's main job: install what is missing, build in Release, and reproduce the paper into out/:
# every figure's data (CSV + JSON), pictures (PNG + SVG) and the report out/index.html.
set -euo pipefail
cd "$(dirname "$0")"
source scripts/setup.sh
funnel_build build --target funnel_apps  # the CLI and the Python package; ./test.sh builds the rest
./build/funnel paper --out out "$@"
echo "funnel: open out/index.html for the report"
