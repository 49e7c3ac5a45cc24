// The paper's own construction of the plane-optimal matrix (Chong & Gortler §2, eq. 1 and
// 3-6), kept as an independent derivation to cross-check the closed form.
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/plane_optimal.h>

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>

namespace lixel {

namespace {

using Matrix11x12 = Eigen::Matrix<double, 11, 12>;

// Hartley normalisation of homogeneous world points: translate the finite ones' centroid to
// the origin, scale their mean distance to sqrt(3), then give every point unit norm (each
// point's equations are homogeneous in it, so its scale is free).
Mat4 WorldNormalization(const std::array<Vec4, 5>& points) {
    Vec3 centroid = Vec3::Zero();
    int finite = 0;
    for (const Vec4& p : points) {
        if (std::abs(p.w()) > 1e-3 * p.head<3>().norm()) {
            centroid += p.head<3>() / p.w();
            ++finite;
        }
    }
    if (finite == 0) return Mat4::Identity();
    centroid /= finite;
    double mean_distance = 0.0;
    for (const Vec4& p : points) {
        if (std::abs(p.w()) > 1e-3 * p.head<3>().norm()) {
            mean_distance += (p.head<3>() / p.w() - centroid).norm();
        }
    }
    mean_distance /= finite;
    const double s = mean_distance > 0.0 ? std::sqrt(3.0) / mean_distance : 1.0;
    Mat4 t = Mat4::Identity() * s;
    t(3, 3) = 1.0;
    t.block<3, 1>(0, 3) = -s * centroid;
    return t;
}

}  // namespace

Result<PlaneOptimalMatrix> SolvePlaneOptimalFivePoint(const PlaneOptimalInput& input) noexcept {
    auto normalized = ValidatePlaneOptimalInput(input);
    if (!normalized) return normalized.error();
    const Vec4& l = normalized->light;
    const Vec4& plane = normalized->plane;
    const Mat4 pixel = PixelMatrix(input.viewer, input.viewport);
    const double g = input.viewport.width;
    const double h = input.viewport.height;

    // Eq. 3-6: the four viewport corners' rays meet P in p^i (homogeneous: the quad Q may
    // straddle infinity, Fig. 5), and must keep their pixel (x, y) in the light image.
    const double corners[4][2] = {{0, 0}, {0, h}, {g, h}, {g, 0}};
    std::array<Vec4, 5> world;  // p^1..p^4, then l (eq. 1)
    for (int i = 0; i < 4; ++i) {
        world[i] = PlanePointAtPixel(pixel, plane, corners[i][0], corners[i][1]);
    }
    world[4] = l;

    const Mat4 t_world = WorldNormalization(world);
    // Image normalisation: centre the viewport, corners at distance sqrt(2).
    const double s_img = std::sqrt(2.0) / std::hypot(0.5 * g, 0.5 * h);
    Mat3 t_img = Mat3::Identity();
    t_img(0, 0) = s_img;
    t_img(1, 1) = s_img;
    t_img(0, 2) = -s_img * 0.5 * g;
    t_img(1, 2) = -s_img * 0.5 * h;

    // Unknowns: the x, y, w rows of the normalised matrix, 12 numbers. Each corner gives
    // m_x.X - u m_w.X = 0 and m_y.X - v m_w.X = 0; the light gives m_j.l = 0 (eq. 1).
    Matrix11x12 a = Matrix11x12::Zero();
    int row = 0;
    for (int i = 0; i < 4; ++i) {
        Vec4 x = t_world * world[i];
        x /= x.norm();
        const Eigen::Vector3d uv = t_img * Eigen::Vector3d(corners[i][0], corners[i][1], 1.0);
        a.block<1, 4>(row, 0) = x.transpose();
        a.block<1, 4>(row, 8) = -uv.x() * x.transpose();
        ++row;
        a.block<1, 4>(row, 4) = x.transpose();
        a.block<1, 4>(row, 8) = -uv.y() * x.transpose();
        ++row;
    }
    Vec4 light = t_world * l;
    light /= light.norm();
    for (int j = 0; j < 3; ++j) a.block<1, 4>(row++, 4 * j) = light.transpose();

    const Eigen::JacobiSVD<Matrix11x12> svd(a, Eigen::ComputeFullV);
    const Eigen::Matrix<double, 12, 1> null = svd.matrixV().col(11);
    const auto& sigma = svd.singularValues();
    if (!(sigma(10) > 1e-13 * sigma(0))) {
        return Error{"plane", "five-point system is rank deficient (corner rays degenerate)"};
    }

    Eigen::Matrix<double, 3, 4> normalized_rows;
    for (int j = 0; j < 3; ++j) normalized_rows.row(j) = null.segment<4>(4 * j).transpose();
    const Eigen::Matrix<double, 3, 4> rows = t_img.inverse() * normalized_rows * t_world;

    Mat4 m = Mat4::Zero();
    m.row(0) = rows.row(0);
    m.row(1) = rows.row(1);
    m.row(3) = rows.row(2);
    const double row_scale = std::max({m.row(0).norm(), m.row(1).norm(), m.row(3).norm()});
    m /= row_scale;

    // Sign (paper §2, Fig. 5): needed points in front of the viewer must get q > 0. The null
    // vector's sign is arbitrary. On P the solved w row is a multiple k a_w of the viewer's
    // (eq. 3-6 fix every plane point's image, so m_w - k a_w vanishes on P and is a multiple of
    // P), and the needed points are those with (a_w . X) X_w > 0, so q > 0 on them iff k > 0:
    // k is read off the w row itself, by least squares in the complement of P, for every view,
    // whichever part of P is visible or however far the horizon lies from the viewport centre.
    const Vec4 a_w = pixel.row(3).transpose();
    const Vec4 m_w = m.row(3).transpose();
    const Vec4 unit_plane = plane / plane.norm();  // (n, d): unit as a 4-vector here
    const Vec4 a_off = a_w - a_w.dot(unit_plane) * unit_plane;
    const Vec4 m_off = m_w - m_w.dot(unit_plane) * unit_plane;
    const double k = m_off.dot(a_off);
    if (!(a_off.norm() > 1e-12 * a_w.norm()) || !(std::abs(k) > 0.0)) {
        return Error{"plane",
                     "is the plane through the viewer's centre parallel to its image "
                     "plane: every point of it images at infinity"};
    }
    if (k < 0.0) m = -m;
    // The factor relative to the closed form (P.l) a_j - (a_j.l) P, whose w row is (P.l) a_w on
    // P: the same rule as SolvePlaneOptimal's.
    const int sign = plane.dot(l) > 0.0 ? 1 : -1;
    return FinishPlaneOptimal(m, sign, pixel, *normalized, input);
}

}  // namespace lixel
