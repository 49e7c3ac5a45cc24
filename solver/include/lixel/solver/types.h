// The small vocabulary every solver unit shares: Eigen double types, the viewport, the
// scene bounds, and the conventions of DESIGN §3 as named values.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lixel {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat4f = Eigen::Matrix4f;
using RowVec4 = Eigen::RowVector4d;

// Clip-space depth convention, used by the solver and by every GL pass: lixel maps store
// z/w in [0, 1] (glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)), 0 nearest the light.
inline constexpr double kClipDepthNear = 0.0;
inline constexpr double kClipDepthFar = 1.0;

// Pixel edges sit at integers and pixel centres at +0.5, in viewer and light images alike.
inline constexpr double kPixelCentreOffset = 0.5;

// Largest image side accepted anywhere (viewer viewport or light map), in pixels.
inline constexpr int kMaxImageSide = 16384;

// A viewer or light image size in pixels; both sides in [1, kMaxImageSide].
struct Viewport {
    int width = 0;
    int height = 0;
};

// Axis-aligned box in world units; min <= max component-wise.
struct Aabb {
    Vec3 min = Vec3::Zero();
    Vec3 max = Vec3::Zero();

    Vec3 Center() const { return 0.5 * (min + max); }
    double Diagonal() const { return (max - min).norm(); }
};

}  // namespace lixel
