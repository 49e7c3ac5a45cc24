#version 450 core
// View pass: per viewer pixel, the map chosen by the plan's lookup rule and the shadow test of
// the method asked for. Outputs the lit fraction (the mask), a shaded preview and the map used.
// The client shader kit (client/glsl): the same lookup rule and tests every client runs.
#include "lixel_shadows.glsl"

in vec3 v_position;

// Matches ShadowMethod in view_pass.h.
const int kMethodDepth = 0;
const int kMethodPcf = 1;
const int kMethodSecondDepth = 2;
const int kMethodSilhouette = 3;

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
uniform int u_pcf_radius;
uniform int u_virtual_samples;
uniform int u_tint_maps;

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_preview;
layout(location = 2) out int o_map;

// Farthest sample of each test from the point, lixels: the nearest texel's centre, the 2r x 2r
// PCF taps' centres (per unit r), a texel's corners.
const float kReachNearest = 0.70710678;
const float kReachPerRadius = 1.41421356;
const float kReachCorners = 1.41421356;

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
    vec3 s;
    int map = lixel_select_map(p, s);
    float lit;
    if (!(n_dot_l > 0.0)) {
        lit = 0.0;  // faces away from the light: shadowed by the illumination model (§3.1)
    } else if (map < 0) {
        lit = 1.0;  // no map holds the point's light ray, so nothing planned casts onto it
    } else {
        vec4 plane = lixel_map_plane[map] * vec4(n, -dot(n, p));
        // Slope-scaled bias: the tangent plane's depth change per lixel times how far the
        // test's farthest sample lies from the point (reach, lixels), so a planar receiver
        // never shadows itself; the boundary moves by at most slope_bias * reach lixels.
        if (kMethod == kMethodDepth) {
            lit = lixel_hard_shadow(map, s, lixel_slope_bias(plane, kReachNearest, u_depth_bias,
                                                             u_slope_bias, u_max_bias));
        } else if (kMethod == kMethodPcf) {
            float reach = kReachPerRadius * float(u_pcf_radius);
            lit = lixel_pcf(map, s,
                            lixel_slope_bias(plane, reach, u_depth_bias, u_slope_bias, u_max_bias),
                            u_pcf_radius);
        } else if (kMethod == kMethodSecondDepth) {
            // An open surface is its own second surface: the bias covers the rounding of its
            // stored depth at this point, in multiples of the bound (the kit's depth section).
            float bias = u_receiver_open != 0
                             ? u_open_second_depth_bias *
                                   lixel_stored_depth_rounding(lixel_map_lixel[map], p)
                             : u_second_depth_bias;
            lit = lixel_second_depth(map, s, plane, bias, u_pcf_radius, u_virtual_samples != 0);
        } else {
            lit = lixel_silhouette_test(map, s, lixel_slope_bias(plane, kReachCorners,
                                                                 u_depth_bias, u_slope_bias,
                                                                 u_max_bias));
        }
    }
#endif
    o_mask = lit;
    o_map = map;
    vec3 albedo = vec3(0.8) * (u_tint_maps != 0 ? map_tint(map) : vec3(1.0));
    vec3 colour = albedo * (0.2 + 0.8 * max(n_dot_l, 0.0) * lit);
    o_preview = vec4(pow(colour, vec3(1.0 / 2.2)), 1.0);  // sRGB-ish for people
}
