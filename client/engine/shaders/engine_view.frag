// The engine client's view, fragment stage: the client shader kit (kit/glsl/lixel_shadows.glsl,
// which EngineView puts before this text, after "#version 450 core" and the defines
// LIXEL_MAX_MAPS, LIXEL_MAX_HALF_PLANES and ENGINE_FILTER) picks the map by the plan's lookup rule
// and runs the filter's test. Outputs the lit fraction (the mask) and a shaded colour.
// Conventions as lixel's own view pass (shaders/view.frag): the facet's normal from the
// derivatives of the relative position, turned toward the eye, and the kit's lixel_shadow for the
// answer (a facet that faces away from the light is shadowed; no map: lit; the slope-scaled bias
// with the reach of each test).

in vec3 v_position;

// EngineFilter's value, the kit's LIXEL_TEST_*: one program per filter, the other tests fold away.
const int kFilter = ENGINE_FILTER;

uniform vec4 u_light;  // relative to the origin: (l_xyz - l_w origin, l_w)
uniform vec4 u_eye;    // the viewer's centre of projection, same convention
uniform float u_depth_bias;
uniform float u_slope_bias;
uniform float u_max_bias;
uniform float u_second_depth_bias;
uniform float u_open_second_depth_bias;
uniform int u_receiver_open;
// The drawn instance receives shadows; one that does not is lit wherever it faces the light
// (lixel's view.frag does the same).
uniform int u_receives = 1;
uniform int u_pcf_radius;
uniform int u_virtual_samples;

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_colour;

void main() {
    vec3 p = v_position;
    vec3 n = cross(dFdx(p), dFdy(p));
    if (dot(n, u_eye.xyz - u_eye.w * p) < 0.0) n = -n;
    n = normalize(n);
    vec3 to_light = normalize(u_light.xyz - u_light.w * p);
    float n_dot_l = dot(n, to_light);

    // The kit's whole answer, the function lixel's own view pass calls: the server's mask.
    LixelShadowSettings settings = LixelShadowSettings(
        u_depth_bias, u_slope_bias, u_max_bias, u_second_depth_bias, u_open_second_depth_bias,
        u_receiver_open != 0, u_pcf_radius, u_virtual_samples != 0);
    int map;
    float lit = lixel_shadow(kFilter, p, n, n_dot_l, settings, map);
    if (u_receives == 0) lit = n_dot_l > 0.0 ? 1.0 : 0.0;
    o_mask = lit;
    vec3 colour = vec3(0.8) * (0.2 + 0.8 * max(n_dot_l, 0.0) * lit);
    o_colour = vec4(pow(colour, vec3(1.0 / 2.2)), 1.0);
}
