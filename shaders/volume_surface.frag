#version 450 core
// Outputs of the view-pass interface (view_pass.h): lit fraction, preview, map index. The
// stencil-volume view writes 0 (shadowed) in the depth draw and 1 (lit) in the draw where the
// count is zero; it uses no maps.

in vec3 v_position;

uniform float u_lit;   // 0 or 1
uniform vec4 u_light;  // relative to the scene's origin

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_preview;
layout(location = 2) out int o_map;

void main() {
    vec3 n = normalize(cross(dFdx(v_position), dFdy(v_position)));
    vec3 to_light = normalize(u_light.xyz - u_light.w * v_position);
    float diffuse = abs(dot(n, to_light));
    float shade = 0.25 + 0.75 * u_lit * diffuse;
    o_mask = u_lit;
    o_preview = vec4(vec3(shade), 1.0);
    o_map = -1;
}
