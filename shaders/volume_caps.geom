#version 450 core
// Paper 001 §2.3: each triangle's facing decided on its reference edge (smallest to largest
// corner), exactly as the multiplicity of its edges was, so caps and sides close every volume.
// Emits the light cap in the light-facing winding and the dark cap, reversed, at infinity.

#include "common_volumes.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 6) out;

in vec3 v_position[];

uniform mat4 u_viewer;
// As in shadow_volume.tese: the triangle and u_light are in the instance's object space.
uniform mat4 u_model = mat4(1.0);
uniform vec4 u_light;

void main() {
    vec3 p[3] = vec3[3](v_position[0], v_position[1], v_position[2]);
    // Sort the corners (three compare-swaps), tracking the permutation's parity.
    vec3 s[3] = p;
    bool odd = false;
    if (lixel_greater(s[0], s[1]) > 0) { vec3 t = s[0]; s[0] = s[1]; s[1] = t; odd = !odd; }
    if (lixel_greater(s[1], s[2]) > 0) { vec3 t = s[1]; s[1] = s[2]; s[2] = t; odd = !odd; }
    if (lixel_greater(s[0], s[1]) > 0) { vec3 t = s[0]; s[0] = s[1]; s[1] = t; odd = !odd; }
    int facing = lixel_comp_multiplicity(s[0], s[1], s[2], u_light);
    if (odd) facing = -facing;
    if (facing == 0) return;  // the light lies in the triangle's plane: no volume
    if (facing < 0) {
        vec3 t = p[1];
        p[1] = p[2];
        p[2] = t;
    }
    for (int k = 0; k < 3; ++k) {
        gl_Position = u_viewer * (u_model * vec4(p[k], 1.0));
        EmitVertex();
    }
    EndPrimitive();
    for (int k = 0; k < 3; ++k) {
        gl_Position = u_viewer * (u_model * lixel_at_infinity(p[(3 - k) % 3], u_light));
        EmitVertex();
    }
    EndPrimitive();
}
