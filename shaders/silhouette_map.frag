#version 450 core
// Silhouette-map pass (paper 000 §3.1, Fig. 4): the point this texel keeps from the edge, in
// texel-local coordinates (origin at the texel's lower-left corner, for precision). An endpoint
// inside the texel; otherwise the edge's intersections with the two diagonals, their midpoint
// when both are inside; no point, no write. The square is enlarged by kCornerMargin so an edge
// through a corner is stored in all four texels around it, and the point is clamped back in.
// Edges hidden from the light are dropped: farther than all four corner depths (the depth map
// offset by half a texel; stored depth, reversed-Z: farther is smaller).

flat in vec4 f_segment;
flat in vec4 f_depth;  // (d q, q) of both endpoints, unclamped
flat in float f_slack;  // rounding bound of the edge's depth (silhouette_map.geom)

uniform sampler2D u_corner_depth;  // (W + 1) x (H + 1): corner (i, j) of texel (i, j) at (i, j)
uniform float u_bias;              // extra stored-depth slack (SilhouetteOptions), default 0

layout(location = 0) out vec2 o_point;

const float kCornerMargin = 1.0 / 64.0;

bool inside(vec2 p) {
    return all(greaterThanEqual(p, vec2(-kCornerMargin))) &&
           all(lessThanEqual(p, vec2(1.0 + kCornerMargin)));
}

// Parameter t on a + t (b - a) where it meets the line through o with direction d, or -1.
float intersect(vec2 a, vec2 b, vec2 o, vec2 d) {
    vec2 e = b - a;
    float den = e.x * d.y - e.y * d.x;
    if (abs(den) < 1e-12) return -1.0;
    vec2 w = o - a;
    return (w.x * d.y - w.y * d.x) / den;
}

void main() {
    ivec2 texel = ivec2(floor(gl_FragCoord.xy));
    vec2 a = f_segment.xy - vec2(texel);
    vec2 b = f_segment.zw - vec2(texel);
    float t;
    if (inside(a)) {
        t = 0.0;
    } else if (inside(b)) {
        t = 1.0;
    } else {
        float t1 = intersect(a, b, vec2(0.0, 0.0), vec2(1.0, 1.0));
        float t2 = intersect(a, b, vec2(0.0, 1.0), vec2(1.0, -1.0));
        bool ok1 = t1 >= 0.0 && t1 <= 1.0 && inside(mix(a, b, t1));
        bool ok2 = t2 >= 0.0 && t2 <= 1.0 && inside(mix(a, b, t2));
        if (ok1 && ok2) {
            t = 0.5 * (t1 + t2);
        } else if (ok1) {
            t = t1;
        } else if (ok2) {
            t = t2;
        } else {
            discard;  // Fig. 4(D): the conservative quad reached a texel the edge misses
        }
    }
    vec2 point = clamp(mix(a, b, t), vec2(0.0), vec2(1.0));
    // Window-space parameter t -> homogeneous parameter u on h0-h1 (t = u q1 / ((1-u) q0 + u q1)),
    // then d = mix(dq) / mix(q): exact at both ends even when one endpoint was clipped near
    // q = 0 and its d is huge, where mixing d itself would cancel. Clamped as the corner map is.
    float q0 = f_depth.y;
    float q1 = f_depth.w;
    float u = t * q0 / ((1.0 - t) * q1 + t * q0);
    float depth = clamp(mix(f_depth.x, f_depth.z, u) / mix(q0, q1, u), 0.0, 1.0);
    float farthest_corner = 1.0;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            farthest_corner = min(farthest_corner,
                                  texelFetch(u_corner_depth, texel + ivec2(i, j), 0).r);
        }
    }
    // Behind every corner by more than the rounding: hidden from the light.
    if (depth + f_slack + u_bias < farthest_corner) discard;
    o_point = point;
}
