# Sourced by scripts/sanitize.sh and scripts/fuzz.sh: the one clang-14 build, instrumented with
# AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer's coverage hooks, that holds both the
# sanitized test suite and the fuzz harnesses, so CI compiles the project under ASan once.
# -O1 with line tables keeps sanitizer reports readable at about a third of -O2 -g's compile
# time; Debug keeps assertions (Eigen's included) on, so a failed one is a reported crash.
configure_asan_build() {
    local root=$1 dir=$2
    CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
        "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -gline-tables-only" -DLIXEL_BUILD_FUZZ=ON \
        -DLIXEL_BUILD_TESTS=ON -DLIXEL_BUILD_BENCH=OFF -DLIXEL_BUILD_EXAMPLES=OFF \
        "-DCMAKE_CROSSCOMPILING_EMULATOR=$root/scripts/sanitizers/run_test.sh" >/dev/null
}
