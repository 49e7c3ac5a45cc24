#version 450 core
// Outputs of the view-pass interface (view_pass.h): lit fraction, preview, map index. The
// shadow-volume view writes 0 (shadowed) in the depth draw and, in the second draw, 1 (lit)
// where the pixel's volume count is zero; it uses no maps.

in vec3 v_position;

uniform float u_lit;   // 0: the depth draw; 1: the lit draw, which reads u_count
uniform vec4 u_light;  // relative to the scene's origin
uniform sampler2D u_count;  // per-pixel volume count (R32F, exact integers), the lit draw only

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_preview;
layout(location = 2) out int o_map;

void main() {
    // Derivatives first: they are undefined in a quad after a discard.
    vec3 n = normalize(cross(dFdx(v_position), dFdy(v_position)));
    vec3 to_light = normalize(u_light.xyz - u_light.w * v_position);
    float diffuse = abs(dot(n, to_light));
    // A pixel inside any volume keeps the shadowed values of the depth draw.
    if (u_lit > 0.5 && texelFetch(u_count, ivec2(gl_FragCoord.xy), 0).r != 0.0) discard;
    float shade = 0.25 + 0.75 * u_lit * diffuse;
    o_mask = u_lit;
    o_preview = vec4(vec3(shade), 1.0);
    o_map = -1;
}
