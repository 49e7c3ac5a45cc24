// Shared by the shadow-volume stages (paper 001): vertex order, multiplicity and the extrusion
// corner map. Each function repeats its C++ twin in server/volumes operation for operation;
// `precise` forbids fused multiply-add and reassociation, so CPU (Arithmetic::kFloat) and GPU
// decide every sign the same way.

// Paper 001, Alg. 2 (vertex_order.h): < 0 when a < b, 0 when equal, > 0 when a > b.
int lixel_greater(vec3 a, vec3 b) {
    ivec3 s = ivec3(greaterThan(a, b)) - ivec3(lessThan(a, b));
    return 4 * s.x + 2 * s.y + s.z;
}

// Paper 001, Alg. 4 (multiplicity.h CompMultiplicity), for a < b < c.
int lixel_comp_multiplicity(vec3 a, vec3 b, vec3 c, vec4 l) {
    precise float xx = c.x - a.x;
    precise float xy = c.y - a.y;
    precise float xz = c.z - a.z;
    precise float yx = l.x - a.x * l.w;
    precise float yy = l.y - a.y * l.w;
    precise float yz = l.z - a.z * l.w;
    precise float nx = xy * yz - xz * yy;
    precise float ny = xz * yx - xx * yz;
    precise float nz = xx * yy - xy * yx;
    precise float d = nx * (b.x - a.x) + ny * (b.y - a.y) + nz * (b.z - a.z);
    return int(sign(d));
}

// Paper 001, Alg. 3: opposite point o's contribution to edge a < b.
int lixel_opposite_contribution(vec3 a, vec3 b, vec3 o, vec4 l) {
    if (lixel_greater(a, o) > 0) return lixel_comp_multiplicity(o, a, b, l);
    if (lixel_greater(b, o) > 0) return -lixel_comp_multiplicity(a, o, b, l);
    return lixel_comp_multiplicity(a, b, o, l);
}

// Paper 001, Alg. 5 (extrusion.h ExtrusionCorner): 0 = A, 1 = B, 2 = A_inf, 3 = B_inf.
int lixel_extrusion_corner(int column, int row) {
    int id = column * 2 + row;
    int t = (id % 2) ^ ((id / 4) % 2);
    int l = ((id + 2) / 4) % 2;
    return t + l * 2;
}

// Paper 001, Eq. 2: a finite point pushed to infinity away from the light.
vec4 lixel_at_infinity(vec3 p, vec4 l) {
    return vec4(l.w * p - l.xyz, 0.0);
}
