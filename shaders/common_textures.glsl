// Per-map textures of the view pass, packed into two atlases (map_atlas.h): one texelFetch per
// tap from one sampler whatever map the fragment picked, since GLSL 4.50 indexes sampler arrays
// only with dynamically uniform expressions.
//   u_atlas_a: depth (depth, PCF), second depth (second depth) or corner depth (silhouette map)
//   u_atlas_b: silhouette points (silhouette map), RG32F
// Map m's texel t lives at u_map_origin_*[m] + t; fetches clamp t to the map's own extent (its
// edge texels, as GL_CLAMP_TO_EDGE would), never reaching a neighbour in the atlas.
// Needs common_maps.glsl (u_map_size: the extent of the silhouette points).

uniform sampler2D u_atlas_a;
uniform sampler2D u_atlas_b;
uniform ivec2 u_map_origin_a[LIXEL_MAX_MAPS];
uniform ivec2 u_map_extent_a[LIXEL_MAX_MAPS];  // corner depth: the map's size plus one
uniform ivec2 u_map_origin_b[LIXEL_MAX_MAPS];

ivec2 clamp_texel(ivec2 texel, ivec2 size) { return clamp(texel, ivec2(0), size - 1); }

vec4 fetch_a(int map, ivec2 texel) {
    return texelFetch(u_atlas_a, u_map_origin_a[map] + clamp_texel(texel, u_map_extent_a[map]),
                      0);
}

vec4 fetch_b(int map, ivec2 texel) {
    return texelFetch(u_atlas_b, u_map_origin_b[map] + clamp_texel(texel, u_map_size[map]), 0);
}
