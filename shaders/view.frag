#version 450 core
// View pass: per viewer pixel, the map chosen by the plan's lookup rule and the shadow test of
// the method asked for. Outputs the lit fraction (the mask), a shaded preview and the map used.
// The client shader kit (kit/glsl): the same lookup rule and tests every client runs.
#include "lixel_shadows.glsl"

in vec3 v_position;

// LIXEL_METHOD is ShadowMethod (view_pass.h), whose values are the kit's LIXEL_TEST_*.
// One program per method (view_pass.cc): constant branches fold away, so a fragment runs its
// own test's code only (SIMD rasterisers such as llvmpipe run both sides of a uniform branch).
const int kMethod = LIXEL_METHOD;
uniform vec4 u_light;  // relative to the origin: (l_xyz - l_w origin, l_w)
uniform vec4 u_eye;    // the viewer's centre of projection, same convention
uniform float u_depth_bias;   // clip-depth units
uniform float u_slope_bias;   // multiple of the tangent plane's depth change over the reach
uniform float u_max_bias;     // clip-depth units; caps the slope term near grazing
uniform float u_second_depth_bias;       // paper 003 §3.3: closed solids, 0 by default
uniform float u_open_second_depth_bias;  // open surfaces: multiple of the depth's rounding
uniform int u_receiver_open;             // the drawn surface is open (GpuMeshRange::closed)
// The drawn instance receives shadows (GpuDraw::receives); one that does not is lit wherever it
// faces the light, as exact visibility counts it (eval/ground_truth.h).
uniform int u_receives = 1;
uniform int u_pcf_radius;
uniform int u_virtual_samples;
uniform int u_tint_maps;

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_preview;
layout(location = 2) out int o_map;

vec3 map_tint(int map) {
    const vec3 palette[4] = vec3[4](vec3(1.0, 0.85, 0.85), vec3(0.85, 1.0, 0.85),
                                    vec3(0.85, 0.85, 1.0), vec3(1.0, 1.0, 0.8));
    return map < 0 ? vec3(1.0, 0.6, 1.0) : palette[map % 4];
}

void main() {
    vec3 p = v_position;
    // The facet's own plane: exact for polygons, so virtual samples on it are exact (§3.2).
    vec3 n = cross(dFdx(p), dFdy(p));
    if (dot(n, u_eye.xyz - u_eye.w * p) < 0.0) n = -n;  // the side the viewer sees
    n = normalize(n);
    vec3 to_light = normalize(u_light.xyz - u_light.w * p);
    float n_dot_l = dot(n, to_light);

#ifdef LIXEL_BARE_VIEW
    // The benchmark's baseline (ViewVariant::kBare): no lookup, no shadow test.
    int map = -1;
    float lit = n_dot_l > 0.0 ? 1.0 : 0.0;
#else
    // The kit's whole answer (lixel_shadow): the same function a client calls.
    LixelShadowSettings settings = LixelShadowSettings(
        u_depth_bias, u_slope_bias, u_max_bias, u_second_depth_bias, u_open_second_depth_bias,
        u_receiver_open != 0, u_pcf_radius, u_virtual_samples != 0);
    int map;
    float lit = lixel_shadow(kMethod, p, n, n_dot_l, settings, map);
    if (u_receives == 0) {
        map = -1;
        lit = n_dot_l > 0.0 ? 1.0 : 0.0;
    }
#endif
    o_mask = lit;
    o_map = map;
    vec3 albedo = vec3(0.8) * (u_tint_maps != 0 ? map_tint(map) : vec3(1.0));
    vec3 colour = albedo * (0.2 + 0.8 * max(n_dot_l, 0.0) * lit);
    o_preview = vec4(pow(colour, vec3(1.0 / 2.2)), 1.0);  // sRGB-ish for people
}
