// Per-map textures of the view pass. GLSL 4.50 indexes sampler arrays only with dynamically
// uniform expressions and the map differs per fragment, so each fetch switches on the index.
//   u_tex_a: depth (depth, PCF), second depth (second depth) or corner depth (silhouette map)
//   u_tex_b: silhouette points (silhouette map), RG32F
// LIXEL_MAX_MAPS must be 8 (the switches below list every map).

uniform sampler2D u_tex_a[8];
uniform sampler2D u_tex_b[8];

ivec2 clamp_texel(ivec2 texel, ivec2 size) { return clamp(texel, ivec2(0), size - 1); }

vec4 fetch_a(int map, ivec2 texel) {
    switch (map) {
        case 0: return texelFetch(u_tex_a[0], clamp_texel(texel, textureSize(u_tex_a[0], 0)), 0);
        case 1: return texelFetch(u_tex_a[1], clamp_texel(texel, textureSize(u_tex_a[1], 0)), 0);
        case 2: return texelFetch(u_tex_a[2], clamp_texel(texel, textureSize(u_tex_a[2], 0)), 0);
        case 3: return texelFetch(u_tex_a[3], clamp_texel(texel, textureSize(u_tex_a[3], 0)), 0);
        case 4: return texelFetch(u_tex_a[4], clamp_texel(texel, textureSize(u_tex_a[4], 0)), 0);
        case 5: return texelFetch(u_tex_a[5], clamp_texel(texel, textureSize(u_tex_a[5], 0)), 0);
        case 6: return texelFetch(u_tex_a[6], clamp_texel(texel, textureSize(u_tex_a[6], 0)), 0);
        default: return texelFetch(u_tex_a[7], clamp_texel(texel, textureSize(u_tex_a[7], 0)), 0);
    }
}

vec4 fetch_b(int map, ivec2 texel) {
    switch (map) {
        case 0: return texelFetch(u_tex_b[0], clamp_texel(texel, textureSize(u_tex_b[0], 0)), 0);
        case 1: return texelFetch(u_tex_b[1], clamp_texel(texel, textureSize(u_tex_b[1], 0)), 0);
        case 2: return texelFetch(u_tex_b[2], clamp_texel(texel, textureSize(u_tex_b[2], 0)), 0);
        case 3: return texelFetch(u_tex_b[3], clamp_texel(texel, textureSize(u_tex_b[3], 0)), 0);
        case 4: return texelFetch(u_tex_b[4], clamp_texel(texel, textureSize(u_tex_b[4], 0)), 0);
        case 5: return texelFetch(u_tex_b[5], clamp_texel(texel, textureSize(u_tex_b[5], 0)), 0);
        case 6: return texelFetch(u_tex_b[6], clamp_texel(texel, textureSize(u_tex_b[6], 0)), 0);
        default: return texelFetch(u_tex_b[7], clamp_texel(texel, textureSize(u_tex_b[7], 0)), 0);
    }
}
