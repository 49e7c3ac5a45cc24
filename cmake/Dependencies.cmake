# Every third-party dependency of lixel is found here, from Debian packages, and nowhere
# else; the rest of the build sees imported targets only. Nothing is downloaded.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)   # libeigen3-dev

if(LIXEL_BUILD_TESTS)
    find_package(GTest REQUIRED)               # libgtest-dev, libgmock-dev
endif()

if(LIXEL_BUILD_BENCH)
    find_package(benchmark REQUIRED)           # libbenchmark-dev
endif()

# --- server/render: headless OpenGL (EGL surfaceless or OSMesa), images -------------------
# GL entry points are loaded at run time through eglGetProcAddress / OSMesaGetProcAddress into a
# per-context table (server/render/src/gl_api.cc), so neither libGL nor libOpenGL is linked:
# OSMesa exports its own gl* symbols, and a process that links both dispatches by link order.
find_package(PkgConfig REQUIRED)
pkg_check_modules(LIXEL_EGL REQUIRED IMPORTED_TARGET egl)        # libegl-dev
pkg_check_modules(LIXEL_OSMESA REQUIRED IMPORTED_TARGET osmesa)  # libosmesa6-dev
find_path(LIXEL_GLCOREARB_DIR GL/glcorearb.h REQUIRED)           # libgl-dev (headers only)
find_package(OpenEXR 3 REQUIRED CONFIG)                          # libopenexr-dev

# --- server/png: previews, mask and difference images ----------------------------------

find_package(PNG REQUIRED)  # libpng-dev

# --- server/eval: exact visibility, scenes ----------------------------------------------

find_package(embree 3 REQUIRED)               # libembree-dev: ground-truth ray casting
find_package(tinyobjloader REQUIRED)          # libtinyobjloader-dev: OBJ scenes
find_package(TinyGLTF REQUIRED)               # libtinygltf-dev: glTF 2.0 scenes
find_program(LIXEL_GNUPLOT gnuplot)           # gnuplot-nox: error_vs_time.png
find_package(TBB REQUIRED CONFIG)             # libtbb-dev: ground truth and metrics run on
                                              # the work-stealing pool Embree builds with
find_package(Threads REQUIRED)                # std::thread: the service's work pool, tests

# --- proto, server/service, client: gRPC and protobuf, metrics ---------------------------
find_package(Protobuf REQUIRED)                           # libprotobuf-dev, protobuf-compiler
find_package(gRPC CONFIG REQUIRED)                        # libgrpc++-dev
find_package(absl CONFIG REQUIRED)                        # libabsl-dev: flags (gRPC's own absl)
find_package(prometheus-cpp CONFIG REQUIRED)              # prometheus-cpp-dev
find_package(OpenSSL REQUIRED)                            # libssl-dev: scene ids (SHA-256)
find_program(LIXEL_PROTOC protoc REQUIRED)                # protobuf-compiler
find_program(LIXEL_GRPC_CPP_PLUGIN grpc_cpp_plugin REQUIRED)        # protobuf-compiler-grpc
find_program(LIXEL_GRPC_PYTHON_PLUGIN grpc_python_plugin)           # protobuf-compiler-grpc

# --- codec: coded maps on the wire -------------------------------------------------------------
# Linked by name (-lzstd -lz), so the installed lixel::codec needs no imported target of ours.
find_path(LIXEL_ZSTD_INCLUDE_DIR zstd.h REQUIRED)         # libzstd-dev
find_library(LIXEL_ZSTD_LIBRARY zstd REQUIRED)            # libzstd-dev
find_path(LIXEL_ZLIB_INCLUDE_DIR zlib.h REQUIRED)         # zlib1g-dev (gRPC's): CRC-32

# --- server/volumes: shadow volumes ---------------------------------------------------------
# lixel::volumes (adjacency, multiplicity, smooth silhouettes) needs Eigen only. lixel::volumes_gl
# loads its extra GL entry points through the EGL and OSMesa libraries found for server/render
# above (PkgConfig::LIXEL_EGL, PkgConfig::LIXEL_OSMESA); nothing new is looked up.

# Warnings shared by every lixel target.
add_library(lixel_warnings INTERFACE)
target_compile_options(lixel_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                                -Wno-sign-conversion)
add_library(lixel::warnings ALIAS lixel_warnings)
