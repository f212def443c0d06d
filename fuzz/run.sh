#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, in build-fuzz) if needed and runs each one
# for SECONDS (default 30), in parallel, from its seed corpus in fuzz/corpus/ (new inputs go to a scratch directory).
# Exits non-zero if a target finds a crash, a sanitizer error, a broken invariant or a hang;
# the input is kept in build-fuzz/fuzz/artifacts/. See docs/robustness.md.
#   fuzz/run.sh [SECONDS]          e.g. fuzz/run.sh 3600 to fuzz for an hour
#   FUNNEL_FUZZ_BUILD=dir          another build directory
#   FUNNEL_FUZZ_JOBS=n             targets run at the same time (default: the number of cores)
#   FUNNEL_FUZZ_SEED=n             libFuzzer's random seed (default: a new one each run)
#   FUNNEL_FUZZ_RUNS=n             stop each target after n executions (SECONDS stays a cap)
# With a seed and a number of runs the campaign is reproducible: the same inputs in the same
# order on every machine (./test.sh runs such a campaign; exploratory fuzzing leaves both unset).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-30}
build=${FUNNEL_FUZZ_BUILD:-build-fuzz}
jobs=${FUNNEL_FUZZ_JOBS:-$(nproc)}
extra=()
if [ -n "${FUNNEL_FUZZ_SEED:-}" ]; then extra+=("-seed=$FUNNEL_FUZZ_SEED"); fi
if [ -n "${FUNNEL_FUZZ_RUNS:-}" ]; then extra+=("-runs=$FUNNEL_FUZZ_RUNS"); fi
targets=(fuzz_parse fuzz_physics)

if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFUNNEL_SANITIZE=ON \
    -DFUNNEL_BUILD_FUZZERS=ON -DFUNNEL_BUILD_TESTS=OFF -DFUNNEL_BUILD_BENCHMARKS=OFF \
    -DFUNNEL_BUILD_PYTHON=OFF -DFUNNEL_LTO=OFF >/dev/null
fi
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

artifacts="$build/fuzz/artifacts"
mkdir -p "$artifacts"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

run_target() {
  local target=$1
  # New inputs go to the first (scratch) directory only: nothing is written into the repository.
  mkdir -p "$scratch/$target"
  "$build/fuzz/$target" -max_total_time="$seconds" -timeout=30 -print_final_stats=1 "${extra[@]}" \
    -artifact_prefix="$artifacts/$target-" "$scratch/$target" fuzz/corpus/"$target" >"$scratch/$target.log" 2>&1
}

status=0
pids=()
for target in "${targets[@]}"; do
  run_target "$target" &
  pids+=($!)
  if [ "${#pids[@]}" -ge "$jobs" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done

for target in "${targets[@]}"; do
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$scratch/$target.log" | tail -n 1)
  if grep -qE '^(==[0-9]+== ?ERROR|SUMMARY: )|invariant violated|runtime error' "$scratch/$target.log"; then
    echo "fuzz: $target FAILED; log:" >&2
    tail -n 60 "$scratch/$target.log" >&2
    status=1
  else
    echo "fuzz: $target ok, ${runs:-?} executions${FUNNEL_FUZZ_SEED:+ from seed $FUNNEL_FUZZ_SEED} (at most ${seconds} s)"
  fi
done
if [ "$status" -ne 0 ]; then
  echo "fuzz: failure; reproduce with $build/fuzz/<target> $artifacts/<file>" >&2
fi
exit "$status"
