#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (ctest).
set -euo pipefail
cd "$(dirname "$0")"
source scripts/setup.sh
funnel_build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

# Sanitizers (docs/robustness.md): each libFuzzer target, built with AddressSanitizer and
# UndefinedBehaviorSanitizer, for 10 000 inputs from a fixed seed (physics invariants over
# random inputs, the command line's parser): the same campaign on every machine, so that a
# test run never fails on a new random find (exploratory fuzzing: fuzz/run.sh SECONDS).
# scripts/sanitize.sh runs every C++ test sanitized too (longer than the 15 minutes CI allows
# this script).
FUNNEL_FUZZ_SEED=1 FUNNEL_FUZZ_RUNS=10000 fuzz/run.sh 90
