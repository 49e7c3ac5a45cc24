// The plan's maps as the view pass sees them, and the lookup rule that picks one (scheduler.h
// LookupRule; paper 004 §3): maps are tried in plan order; a point belongs to the first map whose
// q > 0, whose lixel lies in its lookup rectangle [x0, x1) x [y0, y1) (the map less its guard
// band, LookupRectangle), whose half-planes a x + b y + c >= 0 all hold and whose world limit
// (a cascade's view depth, zero for other maps) has p on its side.
// Expects LIXEL_MAX_MAPS and LIXEL_MAX_HALF_PLANES from the program's defines.

uniform int u_map_count;
// Relative world position -> (x q, y q, d q, q): x, y in lixels, d the stored depth (reversed-Z,
// 1 at the light's near end, 0 at the far end; lixel/solver/light_map.h).
uniform mat4 u_map_lixel[LIXEL_MAX_MAPS];
// ((u_map_lixel)^-1)^T: carries a world plane into light-screen coordinates (paper 003 §3.4).
uniform mat4 u_map_plane[LIXEL_MAX_MAPS];
uniform ivec2 u_map_size[LIXEL_MAX_MAPS];
uniform vec4 u_map_lookup[LIXEL_MAX_MAPS];  // (x0, y0, x1, y1), lixels
uniform int u_map_half_plane_count[LIXEL_MAX_MAPS];
uniform vec3 u_map_half_planes[LIXEL_MAX_MAPS * LIXEL_MAX_HALF_PLANES];
// LookupRule::world_limit on relative positions: accepted where dot(limit, (p, 1)) >= 0.
uniform vec4 u_map_world_limit[LIXEL_MAX_MAPS];

// Index of the map that holds relative position p, or -1; `light_point` gets (x, y, depth).
int select_map(vec3 p, out vec3 light_point) {
    for (int m = 0; m < u_map_count; ++m) {
        vec4 h = u_map_lixel[m] * vec4(p, 1.0);
        if (!(h.w > 0.0)) continue;
        if (dot(u_map_world_limit[m], vec4(p, 1.0)) < 0.0) continue;
        vec3 s = h.xyz / h.w;
        vec4 r = u_map_lookup[m];
        if (s.x < r.x || s.y < r.y || s.x >= r.z || s.y >= r.w) {
            continue;
        }
        bool inside = true;
        for (int k = 0; k < u_map_half_plane_count[m]; ++k) {
            vec3 hp = u_map_half_planes[m * LIXEL_MAX_HALF_PLANES + k];
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
