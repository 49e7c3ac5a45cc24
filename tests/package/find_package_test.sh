#!/usr/bin/env bash
# The installed package as another project sees it: `cmake --install` the build into a fresh
# prefix, configure and build tests/package/consumer against it with find_package(lixel), run it
# against a lixel_server on loopback, and compile the same program with pkg-config's flags.
#   find_package_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$2
work=$(mktemp -d)
server=
trap '[[ -n $server ]] && kill $server 2>/dev/null; rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/lib/cmake/lixel/lixelConfig.cmake"
test -f "$work/prefix/include/lixel/solver/plane_optimal.h"
test -f "$work/prefix/include/lixel/v1/lixel.pb.h"

cmake -S "$source/tests/package/consumer" -B "$work/consumer" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/consumer" > "$work/build.log"

out=$(mktemp -p "$work")
"$build/server/service/lixel_server" --address=127.0.0.1:0 --instance=package --gl=egl \
    > "$out" 2> "$work/server.log" &
server=$!
for _ in $(seq 300); do [[ -s $out ]] && break; sleep 0.1; done
"$work/consumer/lixel_consumer" "127.0.0.1:$(head -1 "$out")"

# pkg-config users: the same program from the .pc file's flags alone.
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig"
g++ "$source/tests/package/consumer/main.cc" -o "$work/pc_consumer" \
    $(pkg-config --cflags lixel) $(pkg-config --libs lixel)
"$work/pc_consumer"
echo "package: find_package and pkg-config consumers built and ran"
