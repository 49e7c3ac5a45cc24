#!/usr/bin/env bash
# Sanitizer runs (docs/reliability.md, "Sanitizers"):
#   1. AddressSanitizer + UndefinedBehaviorSanitizer: the whole test suite, build-asan/.
#   2. ThreadSanitizer: lixel_service_tests only, servers with several GL workers, build-tsan/.
# Either run can be skipped: LIXEL_SANITIZE_RUNS="asan", "tsan" or "asan tsan" (the default).
# Suppressions for uninstrumented third-party code (Mesa, LLVM, Embree, gRPC) live in
# scripts/sanitizers/; none names lixel code.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
jobs=${LIXEL_JOBS:-$(nproc)}
runs=${LIXEL_SANITIZE_RUNS:-asan tsan}
supp=$root/scripts/sanitizers
common=(-G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIXEL_BUILD_TESTS=ON
        -DLIXEL_BUILD_BENCH=OFF -DLIXEL_BUILD_EXAMPLES=OFF)

if [[ " $runs " == *" asan "* ]]; then
    asan_dir=${LIXEL_ASAN_BUILD_DIR:-$root/build-asan}
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1"
    export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    LIXEL_ASAN_RUNTIME=$("${CXX:-g++}" -print-file-name=libasan.so)
    export LIXEL_ASAN_RUNTIME
    start=$SECONDS
    # Test executables run through run_test.sh, which keeps Mesa's driver mapped for LeakSanitizer.
    cmake -S "$root" -B "$asan_dir" "${common[@]}" -DLIXEL_SANITIZE=address,undefined \
          -DCMAKE_CROSSCOMPILING_EMULATOR="$supp/run_test.sh"
    cmake --build "$asan_dir" --parallel "$jobs"
    ctest --test-dir "$asan_dir" --output-on-failure --timeout 1200 -j "$jobs"
    echo "sanitize.sh: ASan+UBSan build and suite: $((SECONDS - start)) s"
    unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS
fi

if [[ " $runs " == *" tsan "* ]]; then
    tsan_dir=${LIXEL_TSAN_BUILD_DIR:-$root/build-tsan}
    export TSAN_OPTIONS="suppressions=$supp/tsan.supp:halt_on_error=1:second_deadlock_stack=1"
    export LIXEL_TEST_WORKERS=${LIXEL_TEST_WORKERS:-4}
    start=$SECONDS
    cmake -S "$root" -B "$tsan_dir" "${common[@]}" -DLIXEL_SANITIZE=thread
    cmake --build "$tsan_dir" --parallel "$jobs" --target lixel_service_tests
    # The Python example needs lixel_server, which this build leaves out.
    ctest --test-dir "$tsan_dir/tests/service" --output-on-failure --timeout 1200 -j "$jobs" \
          -E '^PythonExample'
    echo "sanitize.sh: ThreadSanitizer service tests, $LIXEL_TEST_WORKERS workers: $((SECONDS - start)) s"
fi
