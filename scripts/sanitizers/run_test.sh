#!/usr/bin/env bash
# Runs one sanitized test executable (CMAKE_CROSSCOMPILING_EMULATOR of build-asan/, set by
# scripts/lib/asan_build.sh). It preloads Mesa's swrast_dri.so so the driver stays mapped until
# exit: EGL dlcloses it in its atexit handler, before LeakSanitizer's check, and LeakSanitizer
# could then name neither the driver nor anything in it ("<unknown module>"), so leaks inside Mesa
# could not be told from leaks in lixel. Child processes (lixel_server started by the fault
# tests) inherit the preload. A g++ build links the ASan runtime dynamically and it must come
# first; clang links it into the executable.
set -euo pipefail
preload=
runtime=$(ldd "$1" | awk '/libasan\.so/ {print $3; exit}')
[[ -n $runtime ]] && preload=$runtime
driver=/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so
[[ -e $driver ]] && preload="${preload:+$preload }$driver"
export LD_PRELOAD="$preload${LD_PRELOAD:+ $LD_PRELOAD}"
exec "$@"
