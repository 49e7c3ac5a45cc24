#!/usr/bin/env bash
# The main job: install what is missing, build Release, and run lixel on the built-in
# floor/wall scene: its matrices, then the error-vs-run-time report (report.md, report.csv,
# error_vs_time.png, mask images) in out/report. `main.sh --sweep` reports on every built-in
# scene; every argument is passed on to lixel_report (--help lists them). Output goes to out/
# (or $LIXEL_OUT_DIR).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_BUILD_DIR:-$root/build}
out_dir=${LIXEL_OUT_DIR:-$root/out}

"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"
mkdir -p "$out_dir"
"$build_dir/examples/lixel_floor_wall" | tee "$out_dir/floor_wall.txt"
echo "lixel: wrote $out_dir/floor_wall.txt"
"$build_dir/server/eval/runner/lixel_report" --out "$out_dir/report" "$@"
