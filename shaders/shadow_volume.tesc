#version 450 core
// Paper 001 §2.2, Alg. 3: the edge's multiplicity from its opposite points, then tessellation
// levels (2|m| - 1, 1) so the evaluation stage can fold |m| copies of the side quad (Fig. 1).
// Patch: [A, B, O_1 .. O_k], k = gl_PatchVerticesIn - 2: each draw's patches hold exactly k
// opposite points (volume_scene.h groups edges by their count), so no count vertex is needed.
// gl_PatchVerticesIn <= 32 and k <= 30 keep 2k - 1 <= 64 on llvmpipe.

#include "common_volumes.glsl"

layout(vertices = 2) out;

in vec3 v_position[];
out vec3 tc_position[];
patch out int tc_multiplicity;

// Relative to the scene's origin, in the drawn instance's object space (the light carried back
// by its model matrix); w = 1 point, w = 0 direction.
uniform vec4 u_light;
uniform int u_record;  // 1: write each patch's multiplicity to lixel_multiplicities
uniform int u_patch_base;  // patches drawn before this draw call

layout(std430, binding = 0) buffer LixelMultiplicities {
    int lixel_multiplicities[];
};

void main() {
    vec3 a = v_position[0];
    vec3 b = v_position[1];
    // Alg. 3 needs A < B; the CPU sorted by world position, the shader sees relative floats.
    if (lixel_greater(a, b) > 0) {
        vec3 t = a;
        a = b;
        b = t;
    }
    int m = 0;
    for (int i = 2; i < gl_PatchVerticesIn; ++i) {
        m += lixel_opposite_contribution(a, b, v_position[i], u_light);
    }
    tc_position[gl_InvocationID] = gl_InvocationID == 0 ? a : b;
    if (gl_InvocationID == 0) {
        tc_multiplicity = m;
        if (u_record == 1) lixel_multiplicities[u_patch_base + gl_PrimitiveID] = m;
        // A zero outer level discards the patch: interior edges cost no geometry.
        float level = m == 0 ? 0.0 : float(2 * abs(m) - 1);
        float across = m == 0 ? 0.0 : 1.0;
        gl_TessLevelOuter[0] = across;
        gl_TessLevelOuter[1] = level;
        gl_TessLevelOuter[2] = across;
        gl_TessLevelOuter[3] = level;
        gl_TessLevelInner[0] = level;
        gl_TessLevelInner[1] = across;
    }
}
