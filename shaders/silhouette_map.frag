#version 450 core
// Silhouette-map pass (paper 000 §3.1, Fig. 4): the point this texel keeps from the edge, in
// texel-local coordinates (origin at the texel's lower-left corner, for precision). An endpoint
// inside the texel; otherwise the edge's intersections with the two diagonals, their midpoint
// when both are inside; no point, no write. The square is enlarged by kCornerMargin so an edge
// through a corner is stored in all four texels around it, and the point is clamped back in.
// Edges hidden from the light are dropped: farther than all four corner depths (the depth map
// offset by half a texel).

flat in vec4 f_segment;
flat in vec2 f_depth;

uniform sampler2D u_corner_depth;  // (W + 1) x (H + 1): corner (i, j) of texel (i, j) at (i, j)
uniform float u_bias;              // clip-depth units

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
    // Depth z/q is affine along a projected line in window space.
    float depth = mix(f_depth.x, f_depth.y, t);
    float farthest_corner = 0.0;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            farthest_corner = max(farthest_corner,
                                  texelFetch(u_corner_depth, texel + ivec2(i, j), 0).r);
        }
    }
    if (depth > farthest_corner + u_bias) discard;  // behind every corner: hidden from the light
    o_point = point;
}
