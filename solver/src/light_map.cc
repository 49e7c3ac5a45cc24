// Light-image helpers and the GL factorisation M_l = GLV * GLP (paper 004 §2).
#include <lixel/solver/camera.h>
#include <lixel/solver/light_map.h>

namespace lixel {

Mat4 StoredDepthMatrix(const Mat4& matrix) {
    Mat4 stored = matrix;
    stored.row(2) = matrix.row(3) - matrix.row(2);
    return stored;
}

double StoredDepthOf(const LightMap& map, const Vec4& world_point) {
    const double q = map.matrix.row(3).dot(world_point);
    return (map.matrix.row(3) - map.matrix.row(2)).dot(world_point) / q;
}

Mat4 GlProjection(const LightMap& map) {
    // Inverse of ViewportMatrix({width, height}) applied on the left; z and w pass through.
    Mat4 inverse_viewport = Mat4::Identity();
    inverse_viewport(0, 0) = 2.0 / map.width;
    inverse_viewport(0, 3) = -1.0;
    inverse_viewport(1, 1) = 2.0 / map.height;
    inverse_viewport(1, 3) = -1.0;
    return inverse_viewport * StoredDepthMatrix(map.matrix);
}

GlLightTransform ToGl(const LightMap& map, const Vec3& origin) {
    GlLightTransform gl;
    Mat4 translate = Mat4::Identity();
    translate.block<3, 1>(0, 3) = origin;
    gl.projection = (GlProjection(map) * translate).cast<float>();
    gl.origin = origin;
    gl.width = map.width;
    gl.height = map.height;
    return gl;
}

Vec2 LixelOf(const LightMap& map, const Vec4& world_point) {
    const Vec4 p = map.matrix * world_point;
    return {p.x() / p.w(), p.y() / p.w()};
}

}  // namespace lixel
