#!/usr/bin/env bash
# The main job: install what is missing, build Release, start lixel_server on loopback, and drive
# it with the thin client on the built-in default scene (the paper's floor/wall room): the plan,
# the maps (OpenEXR + PNG), a view mask with its error against exact visibility, and the
# error-vs-run-time report, every method over a 60-frame sequence of the animated room (flicker
# and reallocations), and an engine client's own frames of it from what one Session streams, checked
# against View. Everything lands in out/ (or $LIXEL_OUT_DIR).
#   LIXEL_FULL=1   sweep every built-in scene instead of the default one
#   LIXEL_GL=osmesa  render through OSMesa instead of EGL
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${LIXEL_BUILD_DIR:-$root/build}
out_dir=${LIXEL_OUT_DIR:-$root/out}

"$root/scripts/install_deps.sh"
# Only what this job runs: the server and the thin client (scripts/test.sh builds the rest).
"$root/scripts/build.sh" --target lixel_server lixel_cli
mkdir -p "$out_dir"

server_out=$(mktemp)
"$build_dir/server/service/lixel_server" --address=127.0.0.1:0 --instance=main \
    --gl="${LIXEL_GL:-egl}" > "$server_out" 2> "$out_dir/server.log" &
server=$!
trap 'kill $server 2>/dev/null || true; wait $server 2>/dev/null || true; rm -f "$server_out"' EXIT
for _ in $(seq 300); do [[ -s $server_out ]] && break; sleep 0.1; done
port=$(head -1 "$server_out")
target=127.0.0.1:$port
lixel() { local command=$1; shift; "$build_dir/client/lixel" "$command" --target="$target" "$@"; }
echo "lixel: server on $target (log: $out_dir/server.log)"

lixel plan --scene=floor_wall --second_depth | tee "$out_dir/plan.txt"
lixel solve --scene=floor_wall > "$out_dir/solve.txt"
lixel render --scene=floor_wall --second_depth --out="$out_dir/maps"
lixel view --scene=floor_wall --filter=pcf --evaluate --timings --out="$out_dir/view"
if [[ ${LIXEL_FULL:-0} == 1 ]]; then
    lixel report --full --out="$out_dir/report"
else
    lixel report --scene=floor_wall --out="$out_dir/report"
fi
lixel sequence --scene=floor_wall --frames=60 --size=512 --out="$out_dir/sequence"
# Render's maps coded (docs/service.md, "Coded maps"): depth quantised to the default N per map,
# predicted in space or from the frame before, zstd; the check shows the masks are View's.
lixel frames --scene=floor_wall --frames=60 --size=512 --coherent --check --encoding=quantised \
    --out="$out_dir/frames" > "$out_dir/frames.txt"
tail -5 "$out_dir/frames.txt"
echo "lixel: wrote $out_dir/plan.txt, solve.txt, maps/, view/, report/ (report.md, report.csv," \
     "error_vs_time.png, floor_wall_masks_<test>.png), sequence/ (sequence.md, sequence.csv," \
     "sequence.png), frames/ (frame_*.png, contact_sheet.png) and frames.txt"
