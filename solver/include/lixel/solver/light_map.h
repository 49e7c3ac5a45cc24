// A light image: the world->lixel matrix of one shadow map, its size, and its
// factorisation into what OpenGL takes (DESIGN §3-4).
#pragma once

#include <lixel/solver/types.h>

namespace lixel {

// world point X -> (x q, y q, z q, q): x, y in lixels of a width x height map with lixel
// edges at integers, z in [kClipDepthNear, kClipDepthFar] growing away from the light,
// q > 0 for every point the map must hold.
struct LightMap {
    Mat4 matrix = Mat4::Identity();
    int width = 0;   // lixels, [1, kMaxImageSide]
    int height = 0;  // lixels, [1, kMaxImageSide]
};

// Maps store reversed depth (reversed-Z): d = 1 - z = (r_w - r_z).X / q, 1 at the light's near
// end and 0 at the far end, the value a depth texture holds where nothing was drawn. A perspective
// depth row crowds the receivers against z = 1, where float32 steps are 2^-24; stored as 1 - z
// they sit near 0, where float32 is finest (the floor/wall room's floor: 11x finer steps nearest
// the light, 16x at the far corner; 1700x for a receiver 90 m from a 6 m light). The row is built
// in double, so the cancellation 1 - z happens before the conversion to float.
inline constexpr double kStoredDepthNear = 1.0;  // the light's near end of the depth row
inline constexpr double kStoredDepthFar = 0.0;   // the far end, and texels nothing covers

// `matrix` (LightMap's convention) with its depth row r_z replaced by r_w - r_z: the matrix
// whose z / q is the stored depth d. The x, y and w rows are unchanged.
Mat4 StoredDepthMatrix(const Mat4& matrix);

// Stored depth d of a world point (q > 0), in double.
double StoredDepthOf(const LightMap& map, const Vec4& world_point);

// What a GL pass sets: glViewport(0, 0, width, height) and a projection matrix such that
// ViewportMatrix({width, height}) * projection * Translate(origin) == StoredDepthMatrix(matrix):
// LightMap::matrix in x, y and w, and the stored depth in z (the pass clears to kStoredDepthFar
// and keeps the greatest depth, GL_GREATER).
// Vertices are given relative to `origin` (camera-relative rendering): float keeps a plane
// residual of 1e-3 lixel then, where world coordinates far from the view would cost
// |X| / pixel footprint float ulps.
struct GlLightTransform {
    Mat4f projection;        // (world - origin) -> clip, column-major, stored depth in [0, 1]
    Vec3 origin = Vec3::Zero();  // world units; subtract in double before converting vertices
    int width = 0;
    int height = 0;
};

// The paper's M_l = GLV * GLP (Chong & Gortler §2) with the stored depth row: the projection in
// double, before the last-moment conversion to float.
Mat4 GlProjection(const LightMap& map);
GlLightTransform ToGl(const LightMap& map, const Vec3& origin = Vec3::Zero());

// Light-image (x, y) in lixels of a world point; valid when q > 0.
Vec2 LixelOf(const LightMap& map, const Vec4& world_point);

}  // namespace lixel
