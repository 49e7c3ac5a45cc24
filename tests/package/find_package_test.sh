#!/usr/bin/env bash
# The installed package as another project sees it: `cmake --install` the build into a fresh
# prefix, configure and build tests/package/consumer against it with find_package(lixel), run it
# against a lixel_server on loopback, and compile the same program with pkg-config's flags.
#   find_package_test.sh BUILD_DIR SOURCE_DIR [CXX [FLAGS]]
# CXX and FLAGS: the build's compiler and sanitizer flags, which the consumer must share.
set -euo pipefail
build=$1
source=$2
cxx=${3:-c++}
flags=${4:-}
work=$(mktemp -d)
server=
trap '[[ -n $server ]] && kill $server 2>/dev/null; rm -rf "$work"' EXIT

# A step's log is shown only when it fails.
logged() { local log=$1; shift; "$@" > "$log" 2>&1 || { cat "$log"; return 1; }; }

logged "$work/install.log" cmake --install "$build" --prefix "$work/prefix"
test -f "$work/prefix/lib/cmake/lixel/lixelConfig.cmake"
test -f "$work/prefix/include/lixel/solver/plane_optimal.h"
test -f "$work/prefix/include/lixel/v1/lixel.pb.h"
test -f "$work/prefix/include/lixel/kit/shadow_block.h"
test -f "$work/prefix/include/lixel/client/kit_uploader.h"
test -f "$work/prefix/share/lixel/glsl/lixel_shadows.glsl"

logged "$work/configure.log" cmake -S "$source/tests/package/consumer" -B "$work/consumer" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_CXX_COMPILER="$cxx" \
    "-DCMAKE_CXX_FLAGS=$flags" "-DCMAKE_EXE_LINKER_FLAGS=$flags"
logged "$work/build.log" cmake --build "$work/consumer"

out=$(mktemp -p "$work")
"$build/server/service/lixel_server" --address=127.0.0.1:0 --instance=package --gl=egl \
    > "$out" 2> "$work/server.log" &
server=$!
for _ in $(seq 300); do [[ -s $out ]] && break; sleep 0.1; done
"$work/consumer/lixel_consumer" "127.0.0.1:$(head -1 "$out")"

# pkg-config users: the same program from the .pc file's flags alone.
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig"
# shellcheck disable=SC2086  # flags and pkg-config's output are word lists
"$cxx" $flags "$source/tests/package/consumer/main.cc" -o "$work/pc_consumer" \
    $(pkg-config --cflags lixel) $(pkg-config --libs lixel)
"$work/pc_consumer"
echo "package: find_package and pkg-config consumers built and ran"
