#!/usr/bin/env bash
# Installs the Debian packages funnel needs, if any is missing. Sourced by run.sh and test.sh.
# Works as root or through sudo, non-interactively.
set -euo pipefail

FUNNEL_PACKAGES=(
  build-essential cmake git pkg-config
  libcli11-dev nlohmann-json3-dev libtomlplusplus-dev libeigen3-dev libboost-dev libhwy-dev
  libgtest-dev libbenchmark-dev
  python3-dev pybind11-dev python3-numpy python3-matplotlib python3-pytest python3-tqdm
  python3-pil chromium  # GIF animations (funnel.animate); the report's test in a headless browser
  libopenmpi-dev openmpi-bin  # mpirun over many processes (docs/cluster.md); built without it when absent
  clang libclang-rt-14-dev libomp-14-dev llvm-14  # fuzz/: libFuzzer, OpenMP for clang, llvm-symbolizer
)

funnel_missing_packages() {
  local pkg
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || echo "$pkg"
  done
}

funnel_install() {
  local missing
  missing=$(funnel_missing_packages "$@")
  [ -z "$missing" ] && return 0
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then
      sudo="sudo -n"
    else
      echo "funnel setup: need root or sudo to install:" $missing >&2
      return 1
    fi
  fi
  echo "funnel setup: installing" $missing >&2
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  # shellcheck disable=SC2086
  $sudo apt-get install -y -qq --no-install-recommends $missing >/dev/null
}

funnel_install "${FUNNEL_PACKAGES[@]}"

# Configure and build in Release: funnel_build [DIR [--target T]... [CMAKE_OPTION]...]. The
# directory (default build) and extra CMake options may be given; each --target T builds only T
# (and what it needs) instead of everything.
funnel_build() {
  local dir=${1:-build}
  shift || true
  local options=() targets=()
  while [ $# -gt 0 ]; do
    if [ "$1" = --target ] && [ $# -ge 2 ]; then
      targets+=(--target "$2")
      shift 2
    else
      options+=("$1")
      shift
    fi
  done
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "${options[@]}" >/dev/null
  cmake --build "$dir" -j "$(nproc)" "${targets[@]}"
}
