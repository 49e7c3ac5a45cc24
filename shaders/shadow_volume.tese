#version 450 core
// Paper 001, Alg. 5 and Fig. 1: column u (2|m| - 1 segments) picks a corner pair, A B / C D /
// D C / B A repeating, so even segments are |m| copies of the side quad and odd ones collapse.
// Rows are interpolated linearly rather than rounded: a quad domain with inner level 1 may be
// tessellated as 2 (GL 4.5 §11.2.2.2), and the middle row then lands on the same quad.

#include "common_volumes.glsl"

layout(quads, equal_spacing, ccw) in;

in vec3 tc_position[];
patch in int tc_multiplicity;

uniform mat4 u_viewer;  // relative position -> clip
// The instance's object -> world, relative to the origin (render::GpuDraw::model): the patch's
// points and u_light are in its object space, so the side is extruded there and carried whole.
uniform mat4 u_model = mat4(1.0);
uniform vec4 u_light;

vec4 corner(int id, vec3 a, vec3 b) {
    if (id == 0) return vec4(a, 1.0);
    if (id == 1) return vec4(b, 1.0);
    return lixel_at_infinity(id == 2 ? a : b, u_light);
}

void main() {
    int m = tc_multiplicity;
    // m > 0: the light-facing side runs A -> B and the domain's counter-clockwise quad
    // A, A_inf, B_inf, B is the side (extrusion.cc); m < 0 swaps the edge's ends.
    vec3 a = m > 0 ? tc_position[0] : tc_position[1];
    vec3 b = m > 0 ? tc_position[1] : tc_position[0];
    int segments = 2 * abs(m) - 1;
    int column = int(round(gl_TessCoord.x * float(segments)));
    vec4 p0 = corner(lixel_extrusion_corner(column, 0), a, b);
    vec4 p1 = corner(lixel_extrusion_corner(column, 1), a, b);
    gl_Position = u_viewer * (u_model * mix(p0, p1, gl_TessCoord.y));
}
