#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (ctest).
set -euo pipefail
cd "$(dirname "$0")"
source scripts/setup.sh
funnel_build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

# Sanitizers (docs/robustness.md): each libFuzzer target, built with AddressSanitizer and
# UndefinedBehaviorSanitizer, for 30 s (physics invariants over random inputs, the command
# line's parser). scripts/sanitize.sh runs every C++ test sanitized too (longer than the 15
# minutes CI allows this script).
fuzz/run.sh 30
