// The shadow tests of the view pass, one small function each (STYLE.md): hard_shadow, pcf,
// second_depth_test, silhouette_test. `s` is (x, y, depth) in the chosen map's light screen: x, y
// in lixels with texel edges at integers, depth the stored 1 - z/q in [0, 1], shrinking away
// from the light (reversed-Z, light_map.h): a point is lit when its depth is at least the map's.
// `bias` moves the point toward the light. Each returns the lit fraction in [0, 1]. Needs
// common_maps.glsl and common_textures.glsl.

float lit_if(bool lit) { return lit ? 1.0 : 0.0; }

// Williams' test with a bias: the nearest texel's depth.
float hard_shadow(int map, vec3 s, float bias) {
    return lit_if(s.z + bias >= fetch_a(map, ivec2(floor(s.xy))).r);
}

// Weight of tap i (of 2r along an axis) in the tent filter: the mean of (2r - 1)^2 bilinear
// lookups, which is what hardware PCF does for r = 1 (Reeves et al. 1987).
float tent_weight(int i, int r, float f) {
    if (i == 0) return 1.0 - f;
    if (i == 2 * r - 1) return f;
    return 1.0;
}

// The 2r x 2r taps of PCF and second depth, as r x r blocks of 2 x 2 texels each read by one
// gather_a: block (bi, bj) starts at tap (2 bi, 2 bj) from `base`. Tap weights of a block in
// gather order: (i0, j1), (i1, j1), (i1, j0), (i0, j0).
vec4 block_weights(int bi, int bj, int r, vec2 f) {
    float x0 = tent_weight(2 * bi, r, f.x);
    float x1 = tent_weight(2 * bi + 1, r, f.x);
    float y0 = tent_weight(2 * bj, r, f.y);
    float y1 = tent_weight(2 * bj + 1, r, f.y);
    return vec4(x0 * y1, x1 * y1, x1 * y0, x0 * y0);
}

// Percentage-closer filtering over the 2r x 2r texels whose centres surround s.
float pcf(int map, vec3 s, float bias, int r) {
    vec2 g = s.xy - 0.5;
    ivec2 base = ivec2(floor(g)) - (r - 1);
    vec2 f = g - floor(g);
    float sum = 0.0;
    for (int bj = 0; bj < r; ++bj) {
        for (int bi = 0; bi < r; ++bi) {
            vec4 z = gather_a(map, base + 2 * ivec2(bi, bj));
            vec4 lit = vec4(greaterThanEqual(vec4(s.z + bias), z));
            sum += dot(block_weights(bi, bj, r, f), lit);
        }
    }
    return sum / float((2 * r - 1) * (2 * r - 1));
}

// Paper 003 Fig. 10 against a second-depth map. `plane` is the pixel's tangent plane carried
// into light-screen coordinates, T_L = ((M_PL M_L)^-1)^T T_W (§3.4), so a x + b y + c z + d = 0.
// Trivial accept/reject when all nearby comparisons agree; virtual samples on the tangent plane,
// filtered like PCF, only when they are mixed. The comparison is >= on stored depth, the paper's
// <= (§3.3: two-sided planar surfaces then compare equal to themselves); `bias` defaults to 0. Without `virtual_samples`
// mixed comparisons are filtered as they are (for comparison with §3.2's gain).
float second_depth_test(int map, vec3 s, vec4 plane, float bias, int r, bool virtual_samples) {
    vec2 g = s.xy - 0.5;
    ivec2 base = ivec2(floor(g)) - (r - 1);
    vec2 f = g - floor(g);
    // The tangent plane's depth at every tap centre lies within `reach` of the point's own (the
    // centres are within r lixels per axis): a tap whose stored depth is beyond that band is
    // decided as its virtual sample would be. Plain comparisons alone would reject an open
    // receiver whose taps are its own surface tilted toward the light, and accept one whose
    // taps are tilted away. Without virtual samples, the paper's plain comparisons (reach 0).
    vec2 slope = -plane.xy / plane.z;
    float reach = virtual_samples ? float(r) * (abs(slope.x) + abs(slope.y)) : 0.0;
    if (!(reach < 1e30)) reach = 1e30;  // c ~ 0 (or NaN): nothing is decided early
    float sure_lit = 0.0;
    float sure_shadowed = 0.0;
    float filtered = 0.0;
    for (int bj = 0; bj < r; ++bj) {
        for (int bi = 0; bi < r; ++bi) {
            vec4 z = gather_a(map, base + 2 * ivec2(bi, bj));
            vec4 lit = vec4(greaterThanEqual(vec4(s.z + bias), z));
            filtered += dot(block_weights(bi, bj, r, f), lit);
            sure_lit += dot(vec4(greaterThanEqual(vec4(s.z + bias - reach), z)), vec4(1.0));
            sure_shadowed += dot(vec4(lessThan(vec4(s.z + bias + reach), z)), vec4(1.0));
        }
    }
    float norm = 1.0 / float((2 * r - 1) * (2 * r - 1));
    if (sure_shadowed == float(4 * r * r)) return 0.0;
    if (sure_lit == float(4 * r * r)) return 1.0;
    // A tangent plane that contains the light rays (c ~ 0) has no depth to resample (Fig. 9):
    // keep the ordinary comparisons.
    if (!virtual_samples ||
        abs(plane.z) <= 1e-6 * max(abs(plane.x), max(abs(plane.y), abs(plane.w)))) {
        return filtered * norm;
    }
    float virtual_lit = 0.0;
    for (int bj = 0; bj < r; ++bj) {
        for (int bi = 0; bi < r; ++bi) {
            ivec2 t = base + 2 * ivec2(bi, bj);
            vec4 z_second = gather_a(map, t);
            // Tap centres in gather order, clamped to the map as the texels read are: a tap past
            // the edge reads the edge texel (common_textures.glsl), whose depth belongs to its own
            // centre.
            vec2 last = vec2(u_map_size[map] - 1);
            vec4 cx = clamp(vec4(t.x, t.x + 1, t.x + 1, t.x), 0.0, last.x) + 0.5;
            vec4 cy = clamp(vec4(t.y + 1, t.y + 1, t.y, t.y), 0.0, last.y) + 0.5;
            // The tangent plane's depth at the tap centres, as the point's own depth plus the
            // slope over at most r lixels per axis: -(a x + b y + w) / c evaluated at the
            // centres cancels to a small d near a reversed-Z map's far end and loses it.
            vec4 z_virtual = s.z + slope.x * (cx - s.x) + slope.y * (cy - s.y);
            // A texel nothing covers (stored depth 0) holds no occluder, however far past the
            // depth row's far end the tangent plane extrapolates.
            vec4 lit = max(vec4(greaterThanEqual(z_virtual + bias, z_second)),
                           vec4(lessThanEqual(z_second, vec4(0.0))));
            virtual_lit += dot(block_weights(bi, bj, r, f), lit);
        }
    }
    return virtual_lit * norm;
}

// Silhouette point stored in `texel` (texel-local, empty -> the centre, paper 000 §2), as an
// offset from the texel's lower-left corner. Texels outside the map count as empty.
vec2 silhouette_point(int map, ivec2 texel) {
    if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, u_map_size[map]))) {
        return vec2(0.5);
    }
    vec2 p = fetch_b(map, texel).rg;
    return p.x < 0.0 ? vec2(0.5) : p;
}

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Paper 000 §3.2, Fig. 5. fetch_a reads depth at texel corners (the depth map offset by half a
// texel: corner (i, j) is its texel (i, j)); fetch_b the silhouette points. When the four corner
// tests agree, they decide. Otherwise the segments from this texel's point to its four
// neighbours' points cut the texel into four skewed quadrants, each shaded like its corner; the
// quadrant is found among eight pie slices (the four corner rays, each triangle split by the
// segment to the neighbour across its side).
float silhouette_test(int map, vec3 s, float bias) {
    ivec2 t = ivec2(floor(s.xy));
    vec2 q = s.xy - vec2(t);
    // Corners counter-clockwise from the lower-left.
    const ivec2 corner[4] = ivec2[4](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 1));
    float lit[4];
    for (int k = 0; k < 4; ++k) lit[k] = lit_if(s.z + bias >= fetch_a(map, t + corner[k]).r);
    if (lit[0] == lit[1] && lit[1] == lit[2] && lit[2] == lit[3]) return lit[0];

    // Neighbour across side k (between corner k and k + 1): below, right, above, left.
    const ivec2 side[4] = ivec2[4](ivec2(0, -1), ivec2(1, 0), ivec2(0, 1), ivec2(-1, 0));
    vec2 centre_point = silhouette_point(map, t);
    vec2 v = q - centre_point;
    for (int k = 0; k < 4; ++k) {
        vec2 a = vec2(corner[k]) - centre_point;
        vec2 b = vec2(corner[(k + 1) % 4]) - centre_point;
        if (cross2(a, v) >= 0.0 && cross2(v, b) >= 0.0) {
            vec2 n = silhouette_point(map, t + side[k]) + vec2(side[k]) - centre_point;
            return cross2(n, v) >= 0.0 ? lit[(k + 1) % 4] : lit[k];
        }
    }
    // Only when the point sits exactly on the centre point: take the nearest corner.
    ivec2 nearest = ivec2(greaterThanEqual(q, vec2(0.5)));
    for (int k = 0; k < 4; ++k) {
        if (corner[k] == nearest) return lit[k];
    }
    return lit[0];
}
