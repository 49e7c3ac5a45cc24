// Rounding of the stored depth (reversed-Z, lixel/solver/light_map.h) as a pass computes it:
// d = h.z / h.w with h = m (p, 1) in float, for a map's relative matrix m and a relative
// position p. Each dot product rounds within half an ulp per term, sum_i |m_ri p_i| eps / 2, so
// d is off by at most (sum |m_zi p_i| + |d| sum |m_wi p_i|) eps / (2 |h.w|) to first order. The
// bound scales with the depth row and the position, where a constant tolerance in depth units
// is too large near a map's far end (d ~ 1e-4) and too small near the light.
float stored_depth_rounding(mat4 m, vec3 p) {
    vec4 x = abs(vec4(p, 1.0));
    vec4 z_row = abs(vec4(m[0][2], m[1][2], m[2][2], m[3][2]));
    vec4 w_row = abs(vec4(m[0][3], m[1][3], m[2][3], m[3][3]));
    vec4 h = m * vec4(p, 1.0);
    float d = abs(h.z / h.w);
    return 0.5 * 1.1920929e-7 * (dot(z_row, x) + d * dot(w_row, x)) / abs(h.w);
}
