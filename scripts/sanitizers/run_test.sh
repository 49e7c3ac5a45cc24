#!/usr/bin/env bash
# Runs one sanitized test executable (CMAKE_CROSSCOMPILING_EMULATOR of build-asan/, set by
# scripts/sanitize.sh). It preloads Mesa's swrast_dri.so after the ASan runtime so the driver stays
# mapped until exit: EGL dlcloses it in its atexit handler, before LeakSanitizer's check, and
# LeakSanitizer could then name neither the driver nor anything in it ("<unknown module>"), so
# leaks inside Mesa could not be told from leaks in lixel.
set -euo pipefail
preload="${LIXEL_ASAN_RUNTIME:-$("${CXX:-g++}" -print-file-name=libasan.so)}"
driver=/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so
[[ -e $driver ]] && preload="$preload $driver"
export LD_PRELOAD="$preload${LD_PRELOAD:+ $LD_PRELOAD}"
exec "$@"
