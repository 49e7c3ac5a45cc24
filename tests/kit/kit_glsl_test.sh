#!/usr/bin/env bash
# The client shader kit compiles as what it says it is, for a client that is not lixel: GLSL 4.50
# core and GLSL ES 3.00 (web and mobile), each with every kit function called from a fragment
# shader, checked by Khronos' reference front end (glslangValidator, Debian's glslang-tools).
# lixel's own view pass compiles it as GLSL 4.50 in every render test.
set -euo pipefail
kit=$1
validator=${GLSLANG_VALIDATOR:-glslangValidator}
command -v "$validator" > /dev/null || { echo "$validator not found (apt-get install glslang-tools)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
body='
in vec3 v_position;
out vec4 o_colour;
void main() {
    vec3 s;
    int map = lixel_select_map(v_position, s);
    float lit = 1.0;
    if (map >= 0) {
        vec4 plane = lixel_map_plane[map] * vec4(0.0, 1.0, 0.0, -v_position.y);
        float bias = lixel_slope_bias(plane, 0.70710678, 1e-5, 1.0, 1e-2);
        lit = lixel_hard_shadow(map, s, bias) + lixel_pcf(map, s, bias, 2) +
              lixel_second_depth(map, s, plane, 0.0, 1, true) +
              lixel_silhouette_test(map, s, bias) +
              lixel_stored_depth_rounding(lixel_map_lixel[map], v_position);
    }
    LixelShadowSettings settings =
        LixelShadowSettings(0.0, 1.5, 1.0, 0.0, 16.0, false, 1, true);
    int picked;
    for (int test = LIXEL_TEST_DEPTH; test <= LIXEL_TEST_SILHOUETTE; ++test) {
        lit += lixel_shadow(test, v_position, vec3(0.0, 1.0, 0.0), 0.5, settings, picked);
    }
    o_colour = vec4(lit);
}'
for version in "450 core" "300 es"; do
    file="$work/kit_${version// /_}.frag"
    {
        echo "#version $version"
        cat "$kit"
        echo "$body"
    } > "$file"
    if ! "$validator" -S frag "$file" > "$work/log" 2>&1; then
        echo "the kit does not compile as GLSL $version:"
        cat "$work/log"
        exit 1
    fi
    echo "GLSL $version: compiles"
done
echo "1 passed, 0 failed"
