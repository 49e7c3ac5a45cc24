# libFuzzer + ASan + UBSan instrumentation for the fuzz build (LIXEL_BUILD_FUZZ, scripts/fuzz.sh).
# Libraries get the coverage hooks without libFuzzer's main (fuzzer-no-link); only the harnesses
# in fuzz/ link -fsanitize=fuzzer. UBSan does not recover, so undefined behaviour is a crash.
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "LIXEL_BUILD_FUZZ needs clang (libFuzzer); configure with "
                        "CXX=clang++-14, as scripts/fuzz.sh does")
endif()
if(LIXEL_SANITIZE)
    message(FATAL_ERROR "LIXEL_BUILD_FUZZ sets its own sanitizers; leave LIXEL_SANITIZE empty")
endif()
set(lixel_fuzz_sanitizers -fsanitize=address,undefined -fno-sanitize-recover=all
                          -fno-omit-frame-pointer)
add_compile_options(-fsanitize=fuzzer-no-link ${lixel_fuzz_sanitizers} -g)
add_link_options(${lixel_fuzz_sanitizers})
