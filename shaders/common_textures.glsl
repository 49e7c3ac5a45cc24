// Per-map textures of the view pass, packed into two atlases (map_atlas.h): one texelFetch per
// tap from one sampler whatever map the fragment picked, since GLSL 4.50 indexes sampler arrays
// only with dynamically uniform expressions.
//   u_atlas_a: depth (depth, PCF), second depth (second depth) or corner depth (silhouette map)
//   u_atlas_b: silhouette points (silhouette map), RG32F
// Map m's texel t lives at u_map_origin_*[m] + t. In atlas "a" each map sits inside a border of
// its own edge texels, 4 deep (view_pass.cc, kAtlasBorder): a tap up to 4 texels past the edge
// reads what clamping to the map would, and never a neighbouring map. silhouette_point() bounds
// its own texels before fetch_b.

uniform sampler2D u_atlas_a;
uniform sampler2D u_atlas_b;
uniform vec2 u_atlas_a_texel;  // 1 / the atlas's size, for textureGather
uniform ivec2 u_map_origin_a[LIXEL_MAX_MAPS];
uniform ivec2 u_map_origin_b[LIXEL_MAX_MAPS];

vec4 fetch_a(int map, ivec2 texel) {
    return texelFetch(u_atlas_a, u_map_origin_a[map] + texel, 0);
}

// Texels (t.x, t.y + 1), (t.x + 1, t.y + 1), (t.x + 1, t.y), (t.x, t.y) of map "a" in one
// fetch (textureGather's component order): the point sampled is their shared corner.
vec4 gather_a(int map, ivec2 texel) {
    return textureGather(u_atlas_a, vec2(u_map_origin_a[map] + texel + 1) * u_atlas_a_texel);
}

vec4 fetch_b(int map, ivec2 texel) {
    return texelFetch(u_atlas_b, u_map_origin_b[map] + texel, 0);
}
