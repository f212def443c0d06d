#!/usr/bin/env bash
# Every C++ test (library, CLI, MPI) under AddressSanitizer and UndefinedBehaviorSanitizer, in
# build-asan (docs/robustness.md). ./test.sh runs the library's unit tests only, to stay within
# CI's time; run this before a release or after touching the CLI.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DFUNNEL_SANITIZE=ON \
  -DFUNNEL_BUILD_PYTHON=OFF -DFUNNEL_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-asan -j "$(nproc)"
ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
