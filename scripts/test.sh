#!/usr/bin/env bash
# The whole test suite: install what is missing, build Release with tests, run ctest.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_BUILD_DIR:-$root/build}

"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" -DLIXEL_BUILD_TESTS=ON
ctest --test-dir "$build_dir" --output-on-failure --timeout 1200 -j "${LIXEL_JOBS:-$(nproc)}"
