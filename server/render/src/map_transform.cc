// Light-map matrices as a pass uploads them.
#include <lixel/kit/shadow_block.h>
#include <lixel/render/map_transform.h>
#include <lixel/solver/homogeneous.h>

#include <Eigen/LU>

namespace lixel::render {

MapTransform MakeMapTransform(const LightMap& map, const Vec3& origin) {
    MapTransform t;
    t.clip = ToGl(map, origin).projection;
    // The kit's matrices (lixel/kit/shadow_block.h): passes and clients read the same floats.
    const kit::RelativeMatrices relative = kit::MakeRelativeMatrices(map, origin);
    t.lixel = relative.lixel.cast<float>();
    t.plane = relative.plane.cast<float>();
    t.light_facing_winding = LightFacingWinding(map.matrix);
    t.width = map.width;
    t.height = map.height;
    return t;
}

GLenum LightFacingWinding(const Mat4& matrix) {
    return matrix.determinant() < 0.0 ? GL_CCW : GL_CW;
}

LightMap CornerDepthMap(const LightMap& map) {
    LightMap corners = map;
    // (x q, y q, z q, q) -> ((x + 1/2) q, (y + 1/2) q, z q, q): corner (i, j) of the lixel grid
    // lands on the centre of texel (i, j).
    Mat4 shift = Mat4::Identity();
    shift(0, 3) = 0.5;
    shift(1, 3) = 0.5;
    corners.matrix = shift * map.matrix;
    corners.width = map.width + 1;
    corners.height = map.height + 1;
    return corners;
}

Vec4 RelativePoint(const Vec4& point, const Vec3& origin) {
    return Vec4(point.x() - point.w() * origin.x(), point.y() - point.w() * origin.y(),
                point.z() - point.w() * origin.z(), point.w());
}

Mat4f RelativeMatrix(const Mat4& matrix, const Vec3& origin) {
    return (matrix * Translation(origin)).cast<float>();
}

}  // namespace lixel::render
