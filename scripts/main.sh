#!/usr/bin/env bash
# The main job: install what is missing, build Release, and run lixel on the built-in
# floor/wall scene. Output goes to out/ (or $LIXEL_OUT_DIR).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_BUILD_DIR:-$root/build}
out_dir=${LIXEL_OUT_DIR:-$root/out}

"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"
mkdir -p "$out_dir"
"$build_dir/examples/lixel_floor_wall" | tee "$out_dir/floor_wall.txt"
echo "lixel: wrote $out_dir/floor_wall.txt"
