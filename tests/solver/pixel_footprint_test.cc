// Tests for pixel_footprint.h: a map's lixels per viewer pixel on a plane, exact, against a second
// derivation in long double (the plane's own coordinates through two homographies), and none on
// planes seen edge-on by the eye or the light.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/pixel_footprint.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Uniform;
using Real = long double;

// The reference: P's points as o + alpha t1 + beta t2 map to pixels by G and to lixels by K (each
// 3x3: rows 0, 1 and 3 of the viewer's pixel matrix and of the map's matrix, times the plane's
// basis), so pixel -> lixel is K G^-1, a homography H, whose Jacobian at pixel s is
// (H_2x2 - lixel H_row2) / (H s)_w. Singular values by Eigen's Jacobi SVD, all in long double.
Vec2 ReferenceFootprint(const Mat4& pixel_matrix, const Vec4& plane, const Vec3& point,
                        const LightMap& map, const Vec2& pixel) {
    const Vec3 n = plane.head<3>().normalized();
    const Vec3 t1 = n.unitOrthogonal();
    const Vec3 t2 = n.cross(t1);
    Eigen::Matrix<Real, 4, 3> basis;
    basis.col(0) << t1.cast<Real>(), 0;
    basis.col(1) << t2.cast<Real>(), 0;
    basis.col(2) << point.cast<Real>(), 1;
    const Eigen::Matrix<Real, 4, 3> viewed = pixel_matrix.cast<Real>() * basis;
    const Eigen::Matrix<Real, 4, 3> lit = map.matrix.cast<Real>() * basis;
    Eigen::Matrix<Real, 3, 3> g, k;
    g << viewed.row(0), viewed.row(1), viewed.row(3);
    k << lit.row(0), lit.row(1), lit.row(3);
    const Eigen::Matrix<Real, 3, 3> h = k * g.inverse();
    const Eigen::Matrix<Real, 3, 1> y = h * Eigen::Matrix<Real, 3, 1>(pixel.x(), pixel.y(), 1);
    Eigen::Matrix<Real, 2, 2> jacobian;
    for (int c = 0; c < 2; ++c) {
        for (int r = 0; r < 2; ++r) jacobian(r, c) = (h(r, c) - y(r) / y(2) * h(2, c)) / y(2);
    }
    const Eigen::JacobiSVD<Eigen::Matrix<Real, 2, 2>> svd(jacobian);
    return svd.singularValues().cast<double>();
}

// A receiver of a random plane through a random point near a random view's target, seen in the
// viewport, and a frustum light map fitted around that target as the fallback's are.
struct Sample {
    testing::Configuration view;
    LightMap map;
    Vec3 point;
    Vec4 plane;
    Vec2 pixel;
};

std::optional<LightMap> MapAround(std::mt19937_64& rng, const testing::Configuration& c) {
    const double reach = (c.target - c.eye).norm();
    std::vector<Vec4> corners;
    for (int k = 0; k < 8; ++k) {
        corners.push_back(Point(c.target + reach * Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1),
                                                        Uniform(rng, -1, 1))));
    }
    auto map = FitFrustum(c.light, corners, MapSize{0, 0, 512 * 512});
    if (!map) return std::nullopt;
    return *map;
}

// The pixel `point` images to, when it lies in front of the viewer and in the viewport.
std::optional<Vec2> PixelOf(const testing::Configuration& c, const Vec3& point) {
    const Vec4 v = PixelMatrix(c.viewer, c.viewport) * Point(point);
    if (!(v.w() > 0.0)) return std::nullopt;
    const Vec2 at(v.x() / v.w(), v.y() / v.w());
    if (!(at.x() >= 0.0 && at.y() >= 0.0 && at.x() <= c.viewport.width &&
          at.y() <= c.viewport.height)) {
        return std::nullopt;
    }
    return at;
}

std::vector<Sample> RandomSamples(std::uint64_t seed, int views, int per_view) {
    std::mt19937_64 rng(seed);
    std::vector<Sample> out;
    for (int i = 0; i < views; ++i) {
        const testing::Configuration c = testing::RandomConfiguration(rng);
        const auto map = MapAround(rng, c);
        if (!map) continue;
        const double reach = (c.target - c.eye).norm();
        for (int k = 0; k < per_view; ++k) {
            const Vec3 p = c.target + reach * Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1),
                                                   Uniform(rng, -1, 1));
            const Vec3 n = testing::RandomUnit(rng);
            const auto at = PixelOf(c, p);
            if (at) out.push_back({c, *map, p, Vec4(n.x(), n.y(), n.z(), -n.dot(p)), *at});
        }
    }
    return out;
}

// Over 2 000 random views, maps and receiver planes, each singular value within 4e-9 of the
// reference's, relative. The worst cases lie within a few pixels of a line where the composite
// homography's w vanishes (the plane's horizon, or its points level with the light), where a
// pixel's figure is as ill-conditioned as that distance is small; the median is at rounding.
// Central differences of half a pixel, which these figures were once taken by, miss by up to 100
// times there and by 1e-6 typically.
TEST(PixelFootprints, EqualTheJacobianOfTheComposedHomographyInLongDouble) {
    const std::vector<Sample> samples = RandomSamples(2901, 2000, 20);
    std::vector<double> errors;
    int refused = 0;
    for (const Sample& s : samples) {
        const Mat4 pixel_matrix = PixelMatrix(s.view.viewer, s.view.viewport);
        const auto got = PixelFootprints(pixel_matrix.inverse(), s.map).At(s.plane, s.pixel);
        if (!got) {
            ++refused;
            continue;
        }
        const Vec2 want = ReferenceFootprint(pixel_matrix, s.plane, s.point, s.map, s.pixel);
        for (int i = 0; i < 2; ++i) {
            const double error = std::abs(got->coeff(i) - want(i)) / want(i);
            ASSERT_LE(error, 4e-9) << "singular value " << i << ": " << (*got)(i) << " against "
                                   << want(i) << " at pixel " << s.pixel.transpose();
            errors.push_back(error);
        }
    }
    ASSERT_GT(errors.size(), 20000u);
    // Refused: rays that meet their plane behind the viewer or the light.
    EXPECT_LT(refused, static_cast<int>(samples.size()) / 2);
    std::sort(errors.begin(), errors.end());
    EXPECT_LE(errors[errors.size() / 2], 1e-13);
    std::printf(
        "[ measured ] %zu singular values, %d receivers refused: worst %.2g, median %.2g "
        "relative\n",
        errors.size(), refused, errors.back(), errors[errors.size() / 2]);
}

// A plane through the eye (a face a frustum plane cut) or through the light (a face a map's cone
// cut) has no footprint: its Jacobian is 0, or singular, but for rounding. The same plane turned
// by 1e-5 radians away from that point has one.
TEST(PixelFootprints, PlanesThroughTheEyeOrTheLightHaveNone) {
    std::mt19937_64 rng(2902);
    int through_eye = 0, through_light = 0;
    for (int i = 0; i < 500; ++i) {
        const testing::Configuration c = testing::RandomConfiguration(rng);
        const auto map = MapAround(rng, c);
        if (!map) continue;
        const PixelFootprints footprints(PixelMatrix(c.viewer, c.viewport).inverse(), *map);
        const double reach = (c.target - c.eye).norm();
        const Vec3 p =
            c.target +
            0.3 * reach * Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
        const auto at = PixelOf(c, p);
        if (!at) continue;
        // Directions from p to the eye and to the light (toward it, for a directional light).
        const Vec3 to_light = c.light.w() == 0.0
                                  ? Vec3(c.light.head<3>().normalized())
                                  : Vec3((c.light.head<3>() / c.light.w() - p).normalized());
        const Vec3 towards[2] = {(c.eye - p).normalized(), to_light};
        for (int k = 0; k < 2; ++k) {
            const Vec3 n = towards[k].cross(testing::RandomUnit(rng)).normalized();
            const Vec4 through(n.x(), n.y(), n.z(), -n.dot(p));
            EXPECT_FALSE(footprints.At(through, *at).has_value())
                << (k == 0 ? "eye" : "light") << ", view " << i;
            const Vec3 turned = (n + 1e-5 * towards[k]).normalized();
            const auto tilted =
                footprints.At(Vec4(turned.x(), turned.y(), turned.z(), -turned.dot(p)), *at);
            if (tilted) {
                EXPECT_GT(tilted->y(), 0.0);
                (k == 0 ? through_eye : through_light) += 1;
            }
        }
    }
    // The turned planes are measured, but for those that now meet the ray behind the light or
    // the viewer.
    EXPECT_GT(through_eye, 300);
    EXPECT_GT(through_light, 300);
    std::printf(
        "[ measured ] planes turned 1e-5 from the eye measured at %d receivers, from the "
        "light at %d\n",
        through_eye, through_light);
}

// The closed form against Eigen's Jacobi SVD in long double over random matrices at scales from
// 1e-200 to 1e200, rank-deficient ones among them: the larger value within 4 ulps, the smaller
// within 4 ulps of the larger (|det| / larger inherits the determinant's cancellation).
TEST(SingularValues2x2, MatchJacobiSvdAtEveryScaleAndRank) {
    std::mt19937_64 rng(2903);
    constexpr double kUlp = std::numeric_limits<double>::epsilon();
    for (int i = 0; i < 20000; ++i) {
        Eigen::Matrix2d m;
        m << Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1);
        if (i % 4 == 0) m.col(1) = Uniform(rng, -3, 3) * m.col(0);  // rank 1
        if (i % 8 == 1) m.row(0).setZero();
        m *= std::pow(10.0, Uniform(rng, -200, 200));
        const Vec2 got = SingularValues2x2(m);
        const Eigen::JacobiSVD<Eigen::Matrix<Real, 2, 2>> svd(m.cast<Real>());
        const Real larger = svd.singularValues()(0), smaller = svd.singularValues()(1);
        EXPECT_LE(std::abs(got(0) - larger), 4 * kUlp * larger) << m;
        EXPECT_LE(std::abs(got(1) - smaller), 4 * kUlp * larger) << m;
    }
    EXPECT_EQ(SingularValues2x2(Eigen::Matrix2d::Zero()), Vec2(0, 0));
}

}  // namespace
}  // namespace lixel
