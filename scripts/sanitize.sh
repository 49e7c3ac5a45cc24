#!/usr/bin/env bash
# Sanitizer runs (docs/reliability.md, "Sanitizers"); CI runs both (.ci/run):
#   1. AddressSanitizer + UndefinedBehaviorSanitizer + LeakSanitizer: the whole test suite, in the
#      clang-14 build it shares with the fuzz harnesses (scripts/lib/asan_build.sh), build-asan/,
#      less the reruns labelled "gl_names_reused" and "sweep" (cmake/WholeSuiteTest.cmake says why).
#   2. ThreadSanitizer: the service's concurrency tests (tests/service/concurrency_test.cc: one
#      ShadowService, 4 GL workers, 8 caller threads, no gRPC in between), Render's streaming
#      hand-off (tests/service/render_feed_test.cc, RenderFeed.*) and plans sharing a kept object
#      index across threads (tests/solver/object_index_test.cc, ObjectIndex.*), build-tsan/. Debian's
#      gRPC is not built with TSan; its hand-offs between threads are invisible to TSan, so the
#      gRPC-level suites report hundreds of races inside gRPC's inlined code (docs/reliability.md).
# Either run can be skipped: LIXEL_SANITIZE_RUNS="asan", "tsan" or "asan tsan" (the default).
# Suppressions for uninstrumented third-party code (Mesa, LLVM, Embree, gRPC) live in
# scripts/sanitizers/; none names lixel code.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
jobs=${LIXEL_JOBS:-$(nproc)}
runs=${LIXEL_SANITIZE_RUNS:-asan tsan}
supp=$root/scripts/sanitizers
source "$root/scripts/lib/asan_build.sh"

"$root/scripts/install_deps.sh"

if [[ " $runs " == *" asan "* ]]; then
    asan_dir=${LIXEL_ASAN_BUILD_DIR:-$root/build-asan}
    export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
    export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    start=$SECONDS
    configure_asan_build "$root" "$asan_dir"
    cmake --build "$asan_dir" --parallel "$jobs"
    built=$SECONDS
    ctest --test-dir "$asan_dir" --output-on-failure --timeout 1200 -j "$jobs" \
          --label-exclude '^(gl_names_reused|sweep)$'
    echo "sanitize.sh: ASan+UBSan build $((built - start)) s, suite $((SECONDS - built)) s"
    unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS
fi

if [[ " $runs " == *" tsan "* ]]; then
    tsan_dir=${LIXEL_TSAN_BUILD_DIR:-$root/build-tsan}
    export TSAN_OPTIONS="suppressions=$supp/tsan.supp:halt_on_error=1:second_deadlock_stack=1"
    export LIXEL_TEST_WORKERS=${LIXEL_TEST_WORKERS:-4}
    start=$SECONDS
    cmake -S "$root" -B "$tsan_dir" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
          "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -g1" -DLIXEL_SANITIZE=thread -DLIXEL_BUILD_TESTS=ON \
          -DLIXEL_BUILD_BENCH=OFF -DLIXEL_BUILD_EXAMPLES=OFF >/dev/null
    cmake --build "$tsan_dir" --parallel "$jobs" \
          --target lixel_service_concurrency_tests lixel_object_index_tests
    built=$SECONDS
    ctest --test-dir "$tsan_dir/tests/service" --output-on-failure --timeout 1200 -j "$jobs" \
          -R '^(Concurrency|RenderFeed)\.'
    ctest --test-dir "$tsan_dir/tests/solver" --output-on-failure --timeout 1200 -j "$jobs" \
          -R '^ObjectIndex\.'
    echo "sanitize.sh: ThreadSanitizer concurrency tests ($LIXEL_TEST_WORKERS workers):" \
         "build $((built - start)) s, tests $((SECONDS - built)) s"
fi
