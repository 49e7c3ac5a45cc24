#!/usr/bin/env bash
# Configures and builds lixel in Release into build/ (or $LIXEL_BUILD_DIR).
#   build.sh [CMAKE_ARGS...] [--target NAME...]
# Arguments before --target go to the configure step; names after it are the only targets built
# (every target when none is named).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_BUILD_DIR:-$root/build}
jobs=${LIXEL_JOBS:-$(nproc)}

configure=()
targets=()
while [[ $# -gt 0 && $1 != --target ]]; do configure+=("$1"); shift; done
if [[ $# -gt 0 ]]; then shift; targets=("$@"); fi

cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${configure[@]}"
if [[ ${#targets[@]} -gt 0 ]]; then
    cmake --build "$build_dir" --parallel "$jobs" --target "${targets[@]}"
else
    cmake --build "$build_dir" --parallel "$jobs"
fi
