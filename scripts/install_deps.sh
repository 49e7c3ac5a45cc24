#!/usr/bin/env bash
# Installs the Debian 12 packages lixel builds against, skipping apt entirely when all of
# them are present already. Run as root (or through sudo).
set -euo pipefail

packages=(
    build-essential cmake ninja-build pkg-config
    libeigen3-dev
    libgtest-dev libgmock-dev
    libbenchmark-dev
    libegl-dev libgl-dev libosmesa6-dev libgl1-mesa-dri libegl-mesa0
    libembree-dev libtbb-dev libglm-dev libpng-dev libopenexr-dev
    libtinyobjloader-dev libtinygltf-dev
    gnuplot-nox
    glslang-tools  # tests/kit: the client shader kit compiled as GLSL 4.50 and ES 3.00
    libgrpc++-dev protobuf-compiler-grpc protobuf-compiler libprotobuf-dev
    prometheus-cpp-dev libssl-dev openssl python3-grpcio python3-protobuf
    libzstd-dev zlib1g-dev  # lixel::codec: coded maps (zstd), the header's CRC-32
    python3-numpy python3-zstandard  # client/python: the coded-map decoder
    python3-venv python3-pip python3-setuptools python3-wheel  # its package, pip-installed
    clang-14 libclang-rt-14-dev  # scripts/fuzz.sh: libFuzzer harnesses in fuzz/
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

if ((${#missing[@]} == 0)); then
    echo "lixel: all build dependencies are installed"
    exit 0
fi

echo "lixel: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
