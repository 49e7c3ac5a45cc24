# libFuzzer coverage instrumentation for the fuzz build (LIXEL_BUILD_FUZZ; scripts/fuzz.sh and
# scripts/sanitize.sh share one clang build). Every target gets the coverage hooks without
# libFuzzer's main (fuzzer-no-link); only the harnesses in fuzz/ link -fsanitize=fuzzer. The
# sanitizers come from LIXEL_SANITIZE, which the top-level CMakeLists.txt sets to
# "address,undefined" for this build when it is empty.
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "LIXEL_BUILD_FUZZ needs clang (libFuzzer); configure with "
                        "CXX=clang++-14, as scripts/fuzz.sh does")
endif()
if(NOT LIXEL_SANITIZE MATCHES "address")
    message(FATAL_ERROR "LIXEL_BUILD_FUZZ runs under AddressSanitizer; "
                        "LIXEL_SANITIZE=${LIXEL_SANITIZE} leaves it out")
endif()
add_compile_options(-fsanitize=fuzzer-no-link)
