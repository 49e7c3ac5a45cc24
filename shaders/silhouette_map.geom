#version 450 core
// Silhouette-map pass (paper 000 §3.1, Fig. 3): silhouette edges as seen from the light, each
// drawn as a conservative quad. llvmpipe has no conservative rasterisation and wide lines miss
// texels, so the quad is widened here: every texel the edge touches has its centre within
// sqrt(2)/2 lixel of the edge, and the corner rule (silhouette_map.frag) needs a little more.
// Input is GL_TRIANGLES_ADJACENCY (gpu_scene.h): vertices 0, 2, 4 the triangle, 1, 3, 5 the
// vertex opposite edges 0-2, 2-4, 4-0 in the neighbouring triangle, or a copy of the triangle's
// own opposite vertex at an open boundary.

// The kit's depth convention (kit/glsl/lixel_shadows.glsl).
#include "lixel_shadows.glsl"

layout(triangles_adjacency) in;
layout(triangle_strip, max_vertices = 12) out;

in vec3 v_position[];

uniform mat4 u_lixel;   // relative position -> (x q, y q, d q, q), d the stored depth
uniform vec4 u_light;   // relative to the origin: (l_xyz - l_w origin, l_w)
uniform vec2 u_size;    // map width, height in lixels
// The draw's instance turns orientation (GpuDraw::mirrored): counter-clockwise is its back.
uniform bool u_mirrored = false;

// Half-width and end extension of the quad, lixels: sqrt(2)/2 plus the corner margin.
const float kHalfWidth = 0.75;

flat out vec4 f_segment;  // the clipped edge's endpoints in lixels: (a.x, a.y, b.x, b.y)
// Their homogeneous stored depths (d q, q, d q, q), unclamped: depth is interpolated in
// homogeneous form and clamped per fragment, as GL_DEPTH_CLAMP clamps the corner map's.
flat out vec4 f_depth;
// Rounding bound of the edge's stored depth, stored-depth units (visibility_slack).
flat out float f_slack;

bool faces_light(vec3 a, vec3 b, vec3 c) {
    vec3 n = cross(b - a, c - a);
    return (dot(n, u_light.xyz - u_light.w * a) > 0.0) != u_mirrored;
}

// Clips the homogeneous segment h0-h1 to q > 0 (in front of the light). Depth is not clipped:
// the depth passes clamp it (GL_DEPTH_CLAMP, depth_row.h), and the fragment stage clamps the
// edge's depth the same way, per fragment.
bool clip_front(inout vec4 h0, inout vec4 h1) {
    float eps = 1e-6 * max(abs(h0.w), abs(h1.w));
    float d0 = h0.w - eps;
    float d1 = h1.w - eps;
    if (d0 < 0.0 && d1 < 0.0) return false;
    if (d0 < 0.0) h0 = mix(h0, h1, d0 / (d0 - d1));
    if (d1 < 0.0) h1 = mix(h0, h1, d0 / (d0 - d1));
    return true;
}

// How far the edge's depth may be from the corner map's and still count as the same surface: the
// rounding of the vertex's stored depth (lixel_stored_depth_rounding) on both sides, with room for the
// rasteriser's interpolation of the corner map.
float visibility_slack(vec3 p) { return 32.0 * lixel_stored_depth_rounding(u_lixel, p); }

// Outputs are undefined after EmitVertex, so the flat ones are written with every vertex.
void emit_corner(vec2 lixel, vec4 segment, vec4 depth, float slack) {
    f_segment = segment;
    f_depth = depth;
    f_slack = slack;
    gl_Position = vec4(lixel / u_size * 2.0 - 1.0, 0.5, 1.0);
    EmitVertex();
}

void emit_edge(vec3 p0, vec3 p1) {
    vec4 h0 = u_lixel * vec4(p0, 1.0);
    vec4 h1 = u_lixel * vec4(p1, 1.0);
    if (!clip_front(h0, h1)) return;
    vec2 a = h0.xy / h0.w;
    vec2 b = h1.xy / h1.w;
    vec2 d = b - a;
    float len = length(d);
    vec2 dir = len > 1e-6 ? d / len : vec2(1.0, 0.0);
    vec2 perp = vec2(-dir.y, dir.x) * kHalfWidth;
    vec2 ext = dir * kHalfWidth;
    vec4 segment = vec4(a, b);
    vec4 depth = vec4(h0.zw, h1.zw);
    // The clipped endpoints lie on the edge between p0 and p1; their rounding is that of the
    // original vertices, and only grows near q = 0, where the clamp decides anyway.
    float slack = max(visibility_slack(p0), visibility_slack(p1));
    emit_corner(a - ext - perp, segment, depth, slack);
    emit_corner(a - ext + perp, segment, depth, slack);
    emit_corner(b + ext - perp, segment, depth, slack);
    emit_corner(b + ext + perp, segment, depth, slack);
    EndPrimitive();
}

void main() {
    vec3 p[6];
    for (int i = 0; i < 6; ++i) p[i] = v_position[i];
    bool facing = faces_light(p[0], p[2], p[4]);
    for (int e = 0; e < 3; ++e) {
        vec3 a = p[2 * e];
        vec3 b = p[(2 * e + 2) % 6];
        vec3 across = p[2 * e + 1];
        vec3 own_opposite = p[(2 * e + 4) % 6];
        if (across == own_opposite) {
            // Open boundary: an outline of the surface from every direction.
            emit_edge(a, b);
        } else if (facing && !faces_light(a, across, b)) {
            // Light-facing here, away-facing across: a silhouette, drawn once from this side.
            emit_edge(a, b);
        }
    }
}
