// Viewer cameras and their pixel rows.
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <string>

namespace lixel {

namespace {

// |w| of the unit-norm centre below which it is taken to lie at infinity: a few ulps of the
// cofactors Cross4 sums.
constexpr double kEyeAtInfinity = 1e-15;

}  // namespace

Mat4 LookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
    const Vec3 f = (target - eye).normalized();
    const Vec3 s = f.cross(up).normalized();
    const Vec3 u = s.cross(f);
    Mat4 m = Mat4::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
}

Mat4 Perspective(double fovy_radians, double aspect, double near, double far) {
    const double f = 1.0 / std::tan(0.5 * fovy_radians);
    Mat4 m = Mat4::Zero();
    m(0, 0) = f / aspect;
    m(1, 1) = f;
    m(3, 2) = -1.0;
    if (std::isinf(far)) {
        // z_ndc = 1 - near / z_eye_distance: tends to kClipDepthFar at infinity.
        m(2, 2) = -1.0;
        m(2, 3) = -near;
    } else {
        m(2, 2) = -far / (far - near);
        m(2, 3) = -far * near / (far - near);
    }
    return m;
}

Mat4 Orthographic(double half_width, double half_height, double near, double far) {
    Mat4 m = Mat4::Identity();
    m(0, 0) = 1.0 / half_width;
    m(1, 1) = 1.0 / half_height;
    m(2, 2) = -1.0 / (far - near);
    m(2, 3) = -near / (far - near);
    return m;
}

Mat4 ViewportMatrix(const Viewport& viewport) {
    Mat4 m = Mat4::Identity();
    m(0, 0) = 0.5 * viewport.width;
    m(0, 3) = 0.5 * viewport.width;
    m(1, 1) = 0.5 * viewport.height;
    m(1, 3) = 0.5 * viewport.height;
    return m;
}

Mat4 PixelMatrix(const Mat4& viewer, const Viewport& viewport) {
    return ViewportMatrix(viewport) * viewer;
}

Result<Vec4> EyePoint(const Mat4& viewer) {
    Vec4 eye = Cross4(viewer.row(0).transpose(), viewer.row(1).transpose(),
                      viewer.row(3).transpose());
    const double scale = viewer.row(0).norm() * viewer.row(1).norm() * viewer.row(3).norm();
    if (!(eye.norm() > 1e-14 * scale)) {
        return Error{"viewer", "rows x, y and w are linearly dependent: no centre of projection"};
    }
    eye /= eye.norm();
    // A w within rounding of 0 carries no sign: the eye is at infinity (an orthographic viewer,
    // or a perspective one so far away that its w is noise, which is then set to 0 so no caller
    // divides by it), and the sign that matters is which way along the projection direction the
    // viewer sits. Depth grows away from it in the [0, 1] convention (camera.h), and row z
    // vanishes on no centre of an invertible matrix.
    if (std::abs(eye.w()) > kEyeAtInfinity) {
        if (eye.w() < 0.0) eye = -eye;
        return eye;
    }
    const double depth = viewer.row(2).dot(eye);
    if (!(std::abs(depth) > 0.0)) {
        return Error{"viewer",
                     "depth does not change along the projection direction: the "
                     "matrix is singular"};
    }
    eye.w() = 0.0;
    eye /= eye.norm();
    if (depth > 0.0) eye = -eye;
    return eye;
}

Result<bool> ValidateViewer(const Mat4& viewer, const Viewport& viewport, const char* field) {
    const std::string name = field;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(viewer(r, c))) {
                return Error{name + "[" + std::to_string(c) + "][" + std::to_string(r) + "]",
                             "is not finite (" + std::to_string(viewer(r, c)) + ")"};
            }
        }
    }
    if (viewport.width < 1 || viewport.width > kMaxImageSide) {
        return Error{"viewport.width", "must be in [1, " + std::to_string(kMaxImageSide) +
                                           "], got " + std::to_string(viewport.width)};
    }
    if (viewport.height < 1 || viewport.height > kMaxImageSide) {
        return Error{"viewport.height", "must be in [1, " + std::to_string(kMaxImageSide) +
                                            "], got " + std::to_string(viewport.height)};
    }
    // Scale- and position-free invertibility: move the eye to the origin (the determinant does
    // not change, the entries' sizes do), equilibrate columns (undoes a world scale) and rows;
    // the determinant is then at most 16 (Hadamard) and 0 when the rows are dependent.
    Mat4 normalized = viewer;
    const Vec4 eye = Cross4(viewer.row(0).transpose(), viewer.row(1).transpose(),
                            viewer.row(3).transpose());
    if (eye.allFinite() && eye.w() != 0.0) {
        Mat4 to_eye = Mat4::Identity();
        to_eye.block<3, 1>(0, 3) = eye.head<3>() / eye.w();
        if (to_eye.allFinite()) normalized = viewer * to_eye;
    }
    // One pass each, scaling by the largest entry (no square roots on the per-frame path).
    for (int c = 0; c < 4; ++c) {
        const double m = normalized.col(c).cwiseAbs().maxCoeff();
        if (m > 0.0) normalized.col(c) *= 1.0 / m;
    }
    for (int r = 0; r < 4; ++r) {
        const double m = normalized.row(r).cwiseAbs().maxCoeff();
        if (!(m > 0.0)) {
            return Error{name, "row " + std::to_string(r) + " is zero: the matrix is singular"};
        }
        normalized.row(r) *= 1.0 / m;
    }
    const double volume = std::abs(normalized.determinant());
    if (!(volume > kSingularViewerVolume)) {
        return Error{name, "matrix is singular (normalised determinant " +
                               std::to_string(volume) + ")"};
    }
    return true;
}

}  // namespace lixel
