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

// What a GL pass sets: glViewport(0, 0, width, height) and a projection matrix such that
// ViewportMatrix({width, height}) * projection * Translate(origin) == LightMap::matrix.
// Vertices are given relative to `origin` (camera-relative rendering): float keeps a plane
// residual of 1e-3 lixel then, where world coordinates far from the view would cost
// |X| / pixel footprint float ulps.
struct GlLightTransform {
    Mat4f projection;        // (world - origin) -> clip, column-major, [0, 1] clip depth
    Vec3 origin = Vec3::Zero();  // world units; subtract in double before converting vertices
    int width = 0;
    int height = 0;
};

// The paper's M_l = GLV * GLP (Chong & Gortler §2): the projection in double, before the
// last-moment conversion to float.
Mat4 GlProjection(const LightMap& map);
GlLightTransform ToGl(const LightMap& map, const Vec3& origin = Vec3::Zero());

// Light-image (x, y) in lixels of a world point; valid when q > 0.
Vec2 LixelOf(const LightMap& map, const Vec4& world_point);

}  // namespace lixel
