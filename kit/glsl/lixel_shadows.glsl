// lixel's client shader kit: the lookup rule, the depth convention and the shadow tests that
// lixel's own view pass runs (it includes this file), for any GL 4.50 or GLSL ES 3.00 client.
// Paste it after your #version line (and, for ES, nothing else is needed: precision is set
// below), optionally after defining LIXEL_MAX_MAPS and LIXEL_MAX_HALF_PLANES (defaults 8 and 8;
// they must match the block the application fills, lixel/kit/shadow_block.h).
//
// What the application binds (lixel::kit::BuildShadowBlock and lixel::client::KitFrameOf make
// the bytes and images from what Render streams):
//   - the uniform block LixelShadowMaps, std140, at a binding point of its choice
//     (glUniformBlockBinding: GLSL ES 3.00 has no binding qualifier);
//   - lixel_atlas_a, a sampler2D of every map's stored depth (DEPTH_COMPONENT32F or R32F), each
//     map inside a border of its own edge texels kit::kAtlasBorder deep, NEAREST filtering;
//   - lixel_atlas_b, a sampler2D of the silhouette points (RG32F, no border), for the
//     silhouette test only.
// Positions are relative to the origin the block was built for (kit::MakeKitMap's `origin`):
// p = world position - origin, in float, as the application's vertices should be.
//
// std140 layout of LixelShadowMaps for N = LIXEL_MAX_MAPS, H = LIXEL_MAX_HALF_PLANES (bytes):
//        0  ivec4 lixel_counts               x: maps in use (<= N)
//       16  vec4  lixel_atlas_a_texel        xy: 1 / atlas "a" width, height
//       32  mat4  lixel_map_lixel[N]         relative position -> (x q, y q, d q, q)
//   32+64N  mat4  lixel_map_plane[N]         (lixel_map_lixel^-1)^T: world planes into light screen
//  32+128N  vec4  lixel_map_lookup[N]        (x0, y0, x1, y1): the lookup rectangle, lixels
//  32+144N  vec4  lixel_map_world_limit[N]   accepted where dot(limit, (p, 1)) >= 0 (0: always)
//  32+160N  ivec4 lixel_map_size[N]          (width, height, half-plane count, unshadowed)
//  32+176N  ivec4 lixel_map_origin[N]        (atlas "a" x, y; atlas "b" x, y) of texel (0, 0)
//  32+192N  vec4  lixel_half_planes[N H]     (a, b, c, 0): a x + b y + c >= 0 in lixels
//  size 32 + 192 N + 16 N H (2592 bytes for 8 and 8).

#ifdef GL_ES
precision highp float;
precision highp int;
precision highp sampler2D;
#endif

#ifndef LIXEL_MAX_MAPS
#define LIXEL_MAX_MAPS 8
#endif
#ifndef LIXEL_MAX_HALF_PLANES
#define LIXEL_MAX_HALF_PLANES 8
#endif

layout(std140) uniform LixelShadowMaps {
    ivec4 lixel_counts;
    vec4 lixel_atlas_a_texel;
    mat4 lixel_map_lixel[LIXEL_MAX_MAPS];
    mat4 lixel_map_plane[LIXEL_MAX_MAPS];
    vec4 lixel_map_lookup[LIXEL_MAX_MAPS];
    vec4 lixel_map_world_limit[LIXEL_MAX_MAPS];
    ivec4 lixel_map_size[LIXEL_MAX_MAPS];
    ivec4 lixel_map_origin[LIXEL_MAX_MAPS];
    vec4 lixel_half_planes[LIXEL_MAX_MAPS * LIXEL_MAX_HALF_PLANES];
};

uniform sampler2D lixel_atlas_a;
uniform sampler2D lixel_atlas_b;

// ---------------------------------------------------------------------------------------------
// The depth convention (lixel/solver/light_map.h): a map's stored depth d = h.z / h.w, h =
// lixel_map_lixel[m] (p, 1), is reversed-Z: 1 at the light's near end, 0 at the far end, so a
// point is lit when its depth is at least the map's.
//
// Rounding of d as a pass computes it in float: each dot product rounds within half an ulp per
// term, so d is off by at most (sum |m_zi p_i| + |d| sum |m_wi p_i|) eps / (2 |h.w|) to first
// order. It scales with the depth row and the position, where a constant tolerance in depth
// units is too large near a map's far end (d ~ 1e-4) and too small near the light.
float lixel_stored_depth_rounding(mat4 m, vec3 p) {
    vec4 x = abs(vec4(p, 1.0));
    vec4 z_row = abs(vec4(m[0][2], m[1][2], m[2][2], m[3][2]));
    vec4 w_row = abs(vec4(m[0][3], m[1][3], m[2][3], m[3][3]));
    vec4 h = m * vec4(p, 1.0);
    float d = abs(h.z / h.w);
    return 0.5 * 1.1920929e-7 * (dot(z_row, x) + d * dot(w_row, x)) / abs(h.w);
}

// ---------------------------------------------------------------------------------------------
// The lookup rule (lixel/solver/scheduler.h LookupRule; paper 004 §3): maps are tried in plan
// order; a point belongs to the first map whose q > 0, whose lixel lies in its lookup rectangle
// [x0, x1) x [y0, y1) (the map less its guard band), whose half-planes all hold and whose world
// limit (a cascade's view depth, or an unshadowed entry's plane) has p on its side. Returns the
// map, or -1 (no map holds the point's light ray: nothing planned casts onto it); `light_point`
// gets (x, y, depth). A map with lixel_map_size[m].w != 0 is unshadowed (lixel_unshadowed): no
// caster reaches the rays it accepts, the point is lit, and the map has no texels to read.
int lixel_select_map(vec3 p, out vec3 light_point) {
    for (int m = 0; m < lixel_counts.x; ++m) {
        vec4 h = lixel_map_lixel[m] * vec4(p, 1.0);
        if (!(h.w > 0.0)) continue;
        if (dot(lixel_map_world_limit[m], vec4(p, 1.0)) < 0.0) continue;
        vec3 s = h.xyz / h.w;
        vec4 r = lixel_map_lookup[m];
        if (s.x < r.x || s.y < r.y || s.x >= r.z || s.y >= r.w) continue;
        bool inside = true;
        for (int k = 0; k < lixel_map_size[m].z; ++k) {
            vec4 hp = lixel_half_planes[m * LIXEL_MAX_HALF_PLANES + k];
            if (hp.x * s.x + hp.y * s.y + hp.z < 0.0) {
                inside = false;
                break;
            }
        }
        if (inside) {
            light_point = s;
            return m;
        }
    }
    light_point = vec3(0.0);
    return -1;
}

// Whether map m is an unshadowed entry: a plane's needed polygon outside every caster's
// footprint (lixel/solver/scheduler.h LookupRule::unshadowed), lit by construction.
bool lixel_unshadowed(int m) { return lixel_map_size[m].w != 0; }

// ---------------------------------------------------------------------------------------------
// The maps' texels in the two atlases: map m's texel t lives at its origin + t. In atlas "a"
// each map sits inside a border of its own edge texels, 4 deep: a tap up to 4 texels past the
// edge reads what clamping to the map would, and never a neighbouring map. (One sampler for all
// maps: GLSL 4.50 and ES 3.00 index sampler arrays only with dynamically uniform expressions.)

vec4 lixel_fetch_a(int map, ivec2 texel) {
    return texelFetch(lixel_atlas_a, lixel_map_origin[map].xy + texel, 0);
}

// Texels (t.x, t.y + 1), (t.x + 1, t.y + 1), (t.x + 1, t.y), (t.x, t.y) of map "a" (the order
// of textureGather's components): the point sampled is their shared corner.
vec4 lixel_gather_a(int map, ivec2 texel) {
#ifdef GL_ES
    // GLSL ES 3.00 has no textureGather: the same four texels, one fetch each.
    ivec2 o = lixel_map_origin[map].xy + texel;
    return vec4(texelFetch(lixel_atlas_a, o + ivec2(0, 1), 0).r,
                texelFetch(lixel_atlas_a, o + ivec2(1, 1), 0).r,
                texelFetch(lixel_atlas_a, o + ivec2(1, 0), 0).r,
                texelFetch(lixel_atlas_a, o, 0).r);
#else
    return textureGather(lixel_atlas_a,
                         vec2(lixel_map_origin[map].xy + texel + 1) * lixel_atlas_a_texel.xy);
#endif
}

vec4 lixel_fetch_b(int map, ivec2 texel) {
    return texelFetch(lixel_atlas_b, lixel_map_origin[map].zw + texel, 0);
}

// ---------------------------------------------------------------------------------------------
// The shadow tests. `s` is (x, y, depth) in the chosen map's light screen (lixel_select_map):
// x, y in lixels with texel edges at integers. `bias` moves the point toward the light, in
// stored-depth units. Each returns the lit fraction in [0, 1].

float lixel_lit_if(bool lit) { return lit ? 1.0 : 0.0; }

// Williams' test with a bias: the nearest texel's depth.
float lixel_hard_shadow(int map, vec3 s, float bias) {
    return lixel_lit_if(s.z + bias >= lixel_fetch_a(map, ivec2(floor(s.xy))).r);
}

// Slope-scaled bias (the view pass's): a tangent plane's depth change per lixel, |slope|, times
// how far the test's farthest sample lies from the point (reach, lixels: 0.707 for the hard
// test, 1.414 r for PCF of radius r, 1.414 for the silhouette test's corners), plus a constant,
// capped near grazing. `plane` is the receiver's tangent plane in light screen:
// lixel_map_plane[map] * vec4(n, -dot(n, p)) for its normal n.
float lixel_slope_bias(vec4 plane, float reach, float constant_bias, float slope_bias,
                       float max_bias) {
    vec2 slope = abs(plane.z) > 0.0 ? -plane.xy / plane.z : vec2(1e30);
    return min(constant_bias + slope_bias * reach * length(slope), max_bias);
}

// Weight of tap i (of 2r along an axis) in the tent filter: the mean of (2r - 1)^2 bilinear
// lookups, which is what hardware PCF does for r = 1 (Reeves et al. 1987).
float lixel_tent_weight(int i, int r, float f) {
    if (i == 0) return 1.0 - f;
    if (i == 2 * r - 1) return f;
    return 1.0;
}

// The 2r x 2r taps of PCF and second depth, as r x r blocks of 2 x 2 texels each read by one
// lixel_gather_a: block (bi, bj) starts at tap (2 bi, 2 bj) from `base`. Tap weights of a block
// in gather order: (i0, j1), (i1, j1), (i1, j0), (i0, j0).
vec4 lixel_block_weights(int bi, int bj, int r, vec2 f) {
    float x0 = lixel_tent_weight(2 * bi, r, f.x);
    float x1 = lixel_tent_weight(2 * bi + 1, r, f.x);
    float y0 = lixel_tent_weight(2 * bj, r, f.y);
    float y1 = lixel_tent_weight(2 * bj + 1, r, f.y);
    return vec4(x0 * y1, x1 * y1, x1 * y0, x0 * y0);
}

// Percentage-closer filtering over the 2r x 2r texels whose centres surround s.
float lixel_pcf(int map, vec3 s, float bias, int r) {
    vec2 g = s.xy - 0.5;
    ivec2 base = ivec2(floor(g)) - (r - 1);
    vec2 f = g - floor(g);
    float sum = 0.0;
    for (int bj = 0; bj < r; ++bj) {
        for (int bi = 0; bi < r; ++bi) {
            vec4 z = lixel_gather_a(map, base + 2 * ivec2(bi, bj));
            vec4 lit = vec4(greaterThanEqual(vec4(s.z + bias), z));
            sum += dot(lixel_block_weights(bi, bj, r, f), lit);
        }
    }
    return sum / float((2 * r - 1) * (2 * r - 1));
}

// Paper 003 Fig. 10 against a second-depth map. `plane` is the pixel's tangent plane carried
// into light-screen coordinates, T_L = ((M_PL M_L)^-1)^T T_W (§3.4), so a x + b y + c z + d = 0.
// Trivial accept/reject when all nearby comparisons agree; virtual samples on the tangent plane,
// filtered like PCF, only when they are mixed. The comparison is >= on stored depth, the paper's
// <= (§3.3: two-sided planar surfaces then compare equal to themselves); `bias` defaults to 0.
// Without `virtual_samples` mixed comparisons are filtered as they are (§3.2's baseline).
//
// Where comparisons are mixed, a tap is lit when its virtual sample or the point itself is:
// the virtual sample stands in for the surface along the tap's ray, which exists only where the
// surface does. Past a caster's silhouette from the light (a sphere near its terminator, a post
// thinner than a lixel) the tangent plane runs on through empty space, and a steep one soon
// passes behind the floor there, whose depth the tap holds: its virtual sample reads shadow
// although the point's own depth clears the tap. A tap the point's depth clears holds no second
// surface nearer the light than the point along a ray up to r lixels from its own. Calling it lit
// is wrong only where the shadowing second surface lies nearer the point than the tangent
// plane's depth change over that distance (an occluder within |slope| r of a steep receiver),
// where the depth test's slope bias, 1.5 times the change over its reach, lets light through
// too.
float lixel_second_depth(int map, vec3 s, vec4 plane, float bias, int r, bool virtual_samples) {
    vec2 g = s.xy - 0.5;
    ivec2 base = ivec2(floor(g)) - (r - 1);
    vec2 f = g - floor(g);
    // The tangent plane's depth at every tap centre lies within `reach` of the point's own (the
    // centres are within r lixels per axis): a tap whose stored depth is nearer than that band
    // is shadowed at its virtual sample too. Plain comparisons alone would reject an open
    // receiver whose taps are its own surface tilted toward the light. Without virtual samples,
    // the paper's plain comparisons (reach 0).
    vec2 slope = -plane.xy / plane.z;
    float reach = virtual_samples ? float(r) * (abs(slope.x) + abs(slope.y)) : 0.0;
    if (!(reach < 1e30)) reach = 1e30;  // c ~ 0 (or NaN): nothing is decided early
    float plain_lit = 0.0;
    float sure_shadowed = 0.0;
    float filtered = 0.0;
    for (int bj = 0; bj < r; ++bj) {
        for (int bi = 0; bi < r; ++bi) {
            vec4 z = lixel_gather_a(map, base + 2 * ivec2(bi, bj));
            vec4 lit = vec4(greaterThanEqual(vec4(s.z + bias), z));
            filtered += dot(lixel_block_weights(bi, bj, r, f), lit);
            plain_lit += dot(lit, vec4(1.0));
            sure_shadowed += dot(vec4(lessThan(vec4(s.z + bias + reach), z)), vec4(1.0));
        }
    }
    float norm = 1.0 / float((2 * r - 1) * (2 * r - 1));
    if (sure_shadowed == float(4 * r * r)) return 0.0;
    if (plain_lit == float(4 * r * r)) return 1.0;
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
            vec4 z_second = lixel_gather_a(map, t);
            // Tap centres in gather order, clamped to the map as the texels read are: a tap past
            // the edge reads the edge texel (the atlas border), whose depth belongs to its own
            // centre.
            vec2 last = vec2(lixel_map_size[map].xy - 1);
            vec4 cx = clamp(vec4(t.x, t.x + 1, t.x + 1, t.x), 0.0, last.x) + 0.5;
            vec4 cy = clamp(vec4(t.y + 1, t.y + 1, t.y, t.y), 0.0, last.y) + 0.5;
            // The tangent plane's depth at the tap centres, as the point's own depth plus the
            // slope over at most r lixels per axis: -(a x + b y + w) / c evaluated at the
            // centres cancels to a small d near a reversed-Z map's far end and loses it.
            vec4 z_virtual = s.z + slope.x * (cx - s.x) + slope.y * (cy - s.y);
            // A texel nothing covers (stored depth 0) holds no occluder, however far past the
            // depth row's far end the tangent plane extrapolates.
            vec4 lit = max(max(vec4(greaterThanEqual(z_virtual + bias, z_second)),
                               vec4(greaterThanEqual(vec4(s.z + bias), z_second))),
                           vec4(lessThanEqual(z_second, vec4(0.0))));
            virtual_lit += dot(lixel_block_weights(bi, bj, r, f), lit);
        }
    }
    return virtual_lit * norm;
}

// Silhouette point stored in `texel` (texel-local, empty -> the centre, paper 000 §2), as an
// offset from the texel's lower-left corner. Texels outside the map count as empty.
vec2 lixel_silhouette_point(int map, ivec2 texel) {
    if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, lixel_map_size[map].xy))) {
        return vec2(0.5);
    }
    vec2 p = lixel_fetch_b(map, texel).rg;
    return p.x < 0.0 ? vec2(0.5) : p;
}

float lixel_cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Paper 000 §3.2, Fig. 5. Atlas "a" holds depth at texel corners for this test (the depth map
// offset by half a texel, one texel larger each way: corner (i, j) is its texel (i, j)); atlas
// "b" the silhouette points. When the four corner tests agree, they decide. Otherwise the
// segments from this texel's point to its four neighbours' points cut the texel into four
// skewed quadrants, each shaded like its corner; the quadrant is found among eight pie slices
// (the four corner rays, each triangle split by the segment to the neighbour across its side).
float lixel_silhouette_test(int map, vec3 s, float bias) {
    ivec2 t = ivec2(floor(s.xy));
    vec2 q = s.xy - vec2(t);
    // Corners counter-clockwise from the lower-left.
    const ivec2 corner[4] = ivec2[4](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 1));
    float lit[4];
    for (int k = 0; k < 4; ++k) {
        lit[k] = lixel_lit_if(s.z + bias >= lixel_fetch_a(map, t + corner[k]).r);
    }
    if (lit[0] == lit[1] && lit[1] == lit[2] && lit[2] == lit[3]) return lit[0];

    // Neighbour across side k (between corner k and k + 1): below, right, above, left.
    const ivec2 side[4] = ivec2[4](ivec2(0, -1), ivec2(1, 0), ivec2(0, 1), ivec2(-1, 0));
    vec2 centre_point = lixel_silhouette_point(map, t);
    vec2 v = q - centre_point;
    for (int k = 0; k < 4; ++k) {
        vec2 a = vec2(corner[k]) - centre_point;
        vec2 b = vec2(corner[(k + 1) % 4]) - centre_point;
        if (lixel_cross2(a, v) >= 0.0 && lixel_cross2(v, b) >= 0.0) {
            vec2 n = lixel_silhouette_point(map, t + side[k]) + vec2(side[k]) - centre_point;
            return lixel_cross2(n, v) >= 0.0 ? lit[(k + 1) % 4] : lit[k];
        }
    }
    // Only when the point sits exactly on the centre point: take the nearest corner.
    ivec2 nearest = ivec2(greaterThanEqual(q, vec2(0.5)));
    for (int k = 0; k < 4; ++k) {
        if (corner[k] == nearest) return lit[k];
    }
    return lit[0];
}

// ---------------------------------------------------------------------------------------------
// The view pass's whole answer at a point (what lixel's view.frag computes per pixel): the map
// the lookup rule picks, and the lit fraction of one test with the view pass's slope-scaled bias,
// so a client that calls this gets the server's mask. The test is a constant in each program
// (the branches then fold away).

const int LIXEL_TEST_DEPTH = 0;
const int LIXEL_TEST_PCF = 1;
const int LIXEL_TEST_SECOND_DEPTH = 2;
const int LIXEL_TEST_SILHOUETTE = 3;

// Farthest sample of each test from the point, lixels: the nearest texel's centre, the 2r x 2r
// PCF taps' centres (per unit r), a texel's corners.
const float LIXEL_REACH_NEAREST = 0.70710678;
const float LIXEL_REACH_PER_RADIUS = 1.41421356;
const float LIXEL_REACH_CORNERS = 1.41421356;
// The hard test's reach beyond the point's own distance to its texel's centre, lixels (the float
// error of the point's lixel, 2.4e-5 measured at worst, with room), and its bias for the depths'
// own rounding, in multiples of lixel_stored_depth_rounding.
const float LIXEL_REACH_SLACK = 0.01;
const float LIXEL_ROUNDING_BIAS = 16.0;

// lixel::render::ShadowOptions as the tests read them (the server's defaults: depth_bias 0,
// slope_bias 1.5, max_bias 1, second_depth_bias 0, open_second_depth_bias 16).
struct LixelShadowSettings {
    float depth_bias;              // stored-depth units
    float slope_bias;              // multiple of the tangent plane's depth change over the reach
    float max_bias;                // stored-depth units; caps the slope term near grazing
    float second_depth_bias;       // closed solids (paper 003 §3.3)
    float open_second_depth_bias;  // open surfaces: multiple of the stored depth's rounding
    bool receiver_open;            // the drawn surface is open (two-sided)
    int pcf_radius;                // PCF and second depth: 2r x 2r texels, r in [1, 4]
    bool virtual_samples;          // second depth: virtual samples where comparisons are mixed
};

// At relative position p with the facet's unit normal n (turned toward the viewer) and n_dot_l,
// its cosine to the light: 0 when it faces away from the light (shadowed by the illumination
// model), 1 when no map holds its light ray (nothing planned casts onto it) or the map is
// unshadowed (no caster reaches it), else the test's lit fraction. `map` gets the map the lookup rule picked, or -1.
float lixel_shadow(int test, vec3 p, vec3 n, float n_dot_l, LixelShadowSettings o, out int map) {
    vec3 s;
    map = lixel_select_map(p, s);
    if (!(n_dot_l > 0.0)) return 0.0;
    if (map < 0 || lixel_unshadowed(map)) return 1.0;
    // The facet's tangent plane in the map's light screen (paper 003 §3.4). The slope-scaled
    // bias: the plane's depth change per lixel times the test's reach, so a planar receiver
    // never shadows itself; the boundary moves by at most slope_bias * reach lixels.
    vec4 plane = lixel_map_plane[map] * vec4(n, -dot(n, p));
    if (test == LIXEL_TEST_DEPTH) {
        // The one sample read lies at the texel's centre: the bias need only reach that far
        // (receiver-plane depth bias), plus the float error of s (~1e-4 lixel) and of both
        // depths. A plane map at one lixel per pixel samples each pixel's own light ray, so a
        // receiver on its plane needs almost none, and a shadow that starts at a caster's base
        // starts there.
        float reach = min(length(fract(s.xy) - 0.5) + LIXEL_REACH_SLACK, LIXEL_REACH_NEAREST);
        float bias = lixel_slope_bias(plane, reach, o.depth_bias, o.slope_bias, o.max_bias) +
                     LIXEL_ROUNDING_BIAS * lixel_stored_depth_rounding(lixel_map_lixel[map], p);
        return lixel_hard_shadow(map, s, bias);
    }
    if (test == LIXEL_TEST_PCF) {
        float reach = LIXEL_REACH_PER_RADIUS * float(o.pcf_radius);
        return lixel_pcf(map, s,
                         lixel_slope_bias(plane, reach, o.depth_bias, o.slope_bias, o.max_bias),
                         o.pcf_radius);
    }
    if (test == LIXEL_TEST_SECOND_DEPTH) {
        // An open surface is its own second surface: the bias covers the rounding of its stored
        // depth at this point, in multiples of the bound (the depth convention's section).
        float bias = o.receiver_open
                         ? o.open_second_depth_bias *
                               lixel_stored_depth_rounding(lixel_map_lixel[map], p)
                         : o.second_depth_bias;
        return lixel_second_depth(map, s, plane, bias, o.pcf_radius, o.virtual_samples);
    }
    return lixel_silhouette_test(map, s, lixel_slope_bias(plane, LIXEL_REACH_CORNERS, o.depth_bias,
                                                          o.slope_bias, o.max_bias));
}
