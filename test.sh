#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (ctest).
set -euo pipefail
cd "$(dirname "$0")"
source scripts/setup.sh
funnel_build build
ctest --test-dir build --output-on-failure -j "$(nproc)"
