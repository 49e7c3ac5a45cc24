#!/usr/bin/env bash
# Configures and builds lixel in Release into build/ (or $LIXEL_BUILD_DIR).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_BUILD_DIR:-$root/build}
jobs=${LIXEL_JOBS:-$(nproc)}

cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build_dir" --parallel "$jobs"
