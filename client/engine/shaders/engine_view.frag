// The engine client's view, fragment stage: the client shader kit (client/glsl/lixel_shadows.glsl,
// which EngineView puts before this text, after "#version 450 core" and the defines
// LIXEL_MAX_MAPS, LIXEL_MAX_HALF_PLANES and ENGINE_FILTER) picks the map by the plan's lookup rule
// and runs the filter's test. Outputs the lit fraction (the mask) and a shaded colour.
// Conventions as lixel's own view pass (shaders/view.frag): the facet's normal from the
// derivatives of the relative position, turned toward the eye; a facet that faces away from the
// light is shadowed; no map: lit; the slope-scaled bias with the reach of each test.

in vec3 v_position;

const int kFilterDepth = 0;
const int kFilterPcf = 1;
const int kFilterSecondDepth = 2;
const int kFilterSilhouette = 3;
const int kFilter = ENGINE_FILTER;  // one program per filter: the other tests fold away

uniform vec4 u_light;  // relative to the origin: (l_xyz - l_w origin, l_w)
uniform vec4 u_eye;    // the viewer's centre of projection, same convention
uniform float u_depth_bias;
uniform float u_slope_bias;
uniform float u_max_bias;
uniform float u_second_depth_bias;
uniform float u_open_second_depth_bias;
uniform int u_receiver_open;
uniform int u_pcf_radius;
uniform int u_virtual_samples;

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_colour;

// How far the test's farthest sample lies from the point, lixels.
const float kReachNearest = 0.70710678;
const float kReachPerRadius = 1.41421356;
const float kReachCorners = 1.41421356;  // a texel's corners (the silhouette test)

void main() {
    vec3 p = v_position;
    vec3 n = cross(dFdx(p), dFdy(p));
    if (dot(n, u_eye.xyz - u_eye.w * p) < 0.0) n = -n;
    n = normalize(n);
    vec3 to_light = normalize(u_light.xyz - u_light.w * p);
    float n_dot_l = dot(n, to_light);

    vec3 s;
    int map = lixel_select_map(p, s);
    float lit;
    if (!(n_dot_l > 0.0)) {
        lit = 0.0;
    } else if (map < 0) {
        lit = 1.0;
    } else {
        vec4 plane = lixel_map_plane[map] * vec4(n, -dot(n, p));
        if (kFilter == kFilterDepth) {
            lit = lixel_hard_shadow(map, s, lixel_slope_bias(plane, kReachNearest, u_depth_bias,
                                                             u_slope_bias, u_max_bias));
        } else if (kFilter == kFilterPcf) {
            float reach = kReachPerRadius * float(u_pcf_radius);
            lit = lixel_pcf(map, s,
                            lixel_slope_bias(plane, reach, u_depth_bias, u_slope_bias, u_max_bias),
                            u_pcf_radius);
        } else if (kFilter == kFilterSilhouette) {
            // Paper 000: corner depth in atlas "a", silhouette points in atlas "b".
            lit = lixel_silhouette_test(map, s, lixel_slope_bias(plane, kReachCorners,
                                                                 u_depth_bias, u_slope_bias,
                                                                 u_max_bias));
        } else {
            float bias = u_receiver_open != 0
                             ? u_open_second_depth_bias *
                                   lixel_stored_depth_rounding(lixel_map_lixel[map], p)
                             : u_second_depth_bias;
            lit = lixel_second_depth(map, s, plane, bias, u_pcf_radius, u_virtual_samples != 0);
        }
    }
    o_mask = lit;
    vec3 colour = vec3(0.8) * (0.2 + 0.8 * max(n_dot_l, 0.0) * lit);
    o_colour = vec4(pow(colour, vec3(1.0 / 2.2)), 1.0);
}
