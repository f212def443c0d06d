#!/usr/bin/env bash
# Every C++ test (library, CLI, MPI) under AddressSanitizer and UndefinedBehaviorSanitizer, in
# build-asan (docs/robustness.md). ./test.sh runs the fuzzers sanitized but not the suite, to stay
# within CI's time; run this before a release or after touching the CLI.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DFUNNEL_SANITIZE=ON \
  -DFUNNEL_BUILD_PYTHON=OFF -DFUNNEL_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-asan -j "$(nproc)"
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
status=0
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E '^Mpi\.' || status=1
# Under mpirun, Open MPI keeps memory of its own until the process exits (the library, its
# plugins, its progress thread); scripts/lsan-openmpi.supp suppresses those reports, which needs
# whole stacks (the fast unwinder stops in Open MPI's frames). Any other leak still fails.
ASAN_OPTIONS=$ASAN_OPTIONS:fast_unwind_on_malloc=0 LSAN_OPTIONS=suppressions=$PWD/scripts/lsan-openmpi.supp \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -R '^Mpi\.' || status=1
exit "$status"
