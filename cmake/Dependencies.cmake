# Every third-party dependency of lixel is found here, from Debian packages, and nowhere
# else; the rest of the build sees imported targets only. Nothing is downloaded.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)   # libeigen3-dev

if(LIXEL_BUILD_TESTS)
    find_package(GTest REQUIRED)               # libgtest-dev, libgmock-dev
endif()

if(LIXEL_BUILD_BENCH)
    find_package(benchmark REQUIRED)           # libbenchmark-dev
endif()

# Warnings shared by every lixel target.
add_library(lixel_warnings INTERFACE)
target_compile_options(lixel_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                                -Wno-sign-conversion)
add_library(lixel::warnings ALIAS lixel_warnings)
