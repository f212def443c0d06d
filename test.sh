#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (ctest).
set -euo pipefail
cd "$(dirname "$0")"
source scripts/setup.sh
funnel_build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

# Sanitizers (docs/robustness.md): the C++ suite again under AddressSanitizer and
# UndefinedBehaviorSanitizer (at -O1: at -O0 it runs several times slower), then each fuzz
# target for 30 s. Python is tested by the Release build above.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DFUNNEL_SANITIZE=ON \
  -DFUNNEL_BUILD_PYTHON=OFF -DFUNNEL_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-asan -j "$(nproc)"
ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
fuzz/run.sh 30
