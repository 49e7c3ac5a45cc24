// What a pass needs of one light map, in float, relative to the scene's origin.
#pragma once

#include <lixel/render/gl_api.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/types.h>

namespace lixel::render {

struct MapTransform {
    Mat4f clip;   // relative position -> GL clip for glViewport(0, 0, width, height)
    Mat4f lixel;  // relative position -> (x q, y q, d q, q), lixels and stored depth d = 1 - z
    // ((lixel)^-1)^T in double, then float: carries a relative-world plane into light-screen
    // coordinates (paper 003 §3.4, T_L = ((M_PL M_L)^-1)^T T_W).
    Mat4f plane;
    // glFrontFace argument under which GL_FRONT is the triangles facing the light.
    GLenum light_facing_winding = GL_CCW;
    int width = 0;
    int height = 0;
};

MapTransform MakeMapTransform(const LightMap& map, const Vec3& origin);

// A map's winding rule. With q > 0 on the map's points and depth growing away from the light
// (LightMap's contract), a triangle facing the light has window-space signed area of the sign
// of -det(M): det[MX0, MX1, MX2, Ml] = det(M) det[X0, X1, X2, l] expands to
// 2 A q0 q1 q2 (M l)_z = -det(M) n.(l - l_w X0) with (M l)_z < 0 for depth growing away.
GLenum LightFacingWinding(const Mat4& matrix);

// The depth map offset by half a texel that the silhouette map needs (paper 000 §2-3): texel
// (i, j) samples light-image point (i, j), a corner of silhouette texel (i, j); one lixel larger
// on each side so every texel has its four corners.
LightMap CornerDepthMap(const LightMap& map);

// Homogeneous world point relative to `origin`: (x - w origin, w).
Vec4 RelativePoint(const Vec4& point, const Vec3& origin);

// M * Translate(origin), in double, then float.
Mat4f RelativeMatrix(const Mat4& matrix, const Vec3& origin);

}  // namespace lixel::render
