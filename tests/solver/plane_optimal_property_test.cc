// Tests for plane_optimal.h: seeded random configurations, closed form against the paper's
// five-point construction, and the one-lixel-per-pixel property on the plane.
#include <gtest/gtest.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/plane_optimal.h>

#include <limits>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Configuration;
using testing::RandomConfiguration;
using testing::Uniform;

constexpr int kConfigurations = 10000;

// Largest entry-wise difference of two matrices after scaling each row set to unit norm and
// aligning signs: rows x, y, w together (the 12 numbers of the 11 x 12 system), row z alone.
double RelativeDifference(const Mat4& a, const Mat4& b) {
    Eigen::Matrix<double, 3, 4> xa, xb;
    xa << a.row(0), a.row(1), a.row(3);
    xb << b.row(0), b.row(1), b.row(3);
    xa /= xa.norm();
    xb /= xb.norm();
    const double xyw = std::min((xa - xb).cwiseAbs().maxCoeff(), (xa + xb).cwiseAbs().maxCoeff());
    const RowVec4 za = a.row(2) / a.row(2).norm();
    const RowVec4 zb = b.row(2) / b.row(2).norm();
    const double z = std::min((za - zb).cwiseAbs().maxCoeff(), (za + zb).cwiseAbs().maxCoeff());
    return std::max(xyw, z);
}

TEST(PlaneOptimalProperty, ClosedFormAgreesWithFivePointConstruction) {
    std::mt19937_64 rng(12351);
    double worst = 0.0;
    for (int i = 0; i < kConfigurations; ++i) {
        const Configuration c = RandomConfiguration(rng);
        const auto closed = SolvePlaneOptimal(c.Input());
        const auto five = SolvePlaneOptimalFivePoint(c.Input());
        ASSERT_TRUE(closed.ok()) << i << ": " << closed.error().Message();
        ASSERT_TRUE(five.ok()) << i << ": " << five.error().Message();
        const double diff = RelativeDifference(closed->matrix, five->matrix);
        worst = std::max(worst, diff);
        ASSERT_LE(diff, 1e-10) << "configuration " << i;
        // Both chose the orientation that puts the needed points in front (paper Fig. 5).
        EXPECT_GT(closed->matrix.row(3).dot(five->matrix.row(3)), 0.0) << "configuration " << i;
    }
    RecordProperty("worst_relative_difference", std::to_string(worst));
}

TEST(PlaneOptimalProperty, PlanePointsKeepTheirPixelAndLightMapsToItsCentre) {
    std::mt19937_64 rng(20040621);
    double worst = 0.0;
    for (int i = 0; i < kConfigurations; ++i) {
        const Configuration c = RandomConfiguration(rng);
        const auto solved = SolvePlaneOptimal(c.Input());
        ASSERT_TRUE(solved.ok()) << i << ": " << solved.error().Message();
        const Mat4& m = solved->matrix;
        const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);

        // Random pixels whose ray meets P in front of the viewer: the plane point under them,
        // kept homogeneous so points near the horizon are as exact as any other.
        int tested = 0;
        for (int k = 0; k < 16; ++k) {
            const double u = Uniform(rng, 0.0, c.viewport.width);
            const double v = Uniform(rng, 0.0, c.viewport.height);
            const Vec4 x = PlanePointAtPixel(pixel, solved->plane, u, v);
            if (pixel.row(3).dot(x) * x.w() <= 0.0) continue;  // beyond the horizon
            const Vec4 image = m * x;
            ASSERT_GT(image.w() * x.w(), 0.0) << "needed point behind the light image, config " << i;
            const double error = std::hypot(image.x() / image.w() - u, image.y() / image.w() - v);
            worst = std::max(worst, error);
            ASSERT_LE(error, 1e-6) << "configuration " << i << " pixel " << u << ", " << v;
            ++tested;
        }
        ASSERT_GT(tested, 0) << "configuration " << i << " shows none of its plane";

        // Eq. 1: the light images to [0, 0, 1, 0] up to scale.
        const Vec4 l = m * solved->light;
        const double scale = m.norm() * solved->light.norm();
        EXPECT_LE(std::abs(l.x()), 1e-13 * scale) << i;
        EXPECT_LE(std::abs(l.y()), 1e-13 * scale) << i;
        EXPECT_LE(std::abs(l.w()), 1e-13 * scale) << i;
        EXPECT_GT(std::abs(l.z()), 1e-9 * m.row(2).norm() * solved->light.norm()) << i;
    }
    RecordProperty("worst_pixel_error", std::to_string(worst));
}

TEST(PlaneOptimalProperty, CroppedMapsKeepOneLixelPerPixelOnTheNeededPolygon) {
    std::mt19937_64 rng(777);
    for (int i = 0; i < kConfigurations / 10; ++i) {
        const Configuration c = RandomConfiguration(rng);
        PlaneMapRequest request;
        request.input = c.Input();
        request.bounds = c.bounds;
        const auto map = SolvePlaneMap(request);
        ASSERT_TRUE(map.ok()) << i << ": " << map.error().Message();
        EXPECT_LE(map->diagnostics.residual_lixels, 1e-6) << i;
        EXPECT_GT(map->diagnostics.samples, 0);
        EXPECT_LE(map->crop.map.width, c.viewport.width + 1) << i;
        EXPECT_LE(map->crop.map.height, c.viewport.height + 1) << i;
        // Every needed vertex lies in the map, in front of the light image, depth in [0, 1].
        for (const Vec3& p : map->needed_polygon) {
            const Vec4 image = map->crop.map.matrix * Point(p);
            ASSERT_GT(image.w(), 0.0);
            EXPECT_GE(image.x() / image.w(), -1e-7);
            EXPECT_LE(image.x() / image.w(), map->crop.map.width + 1e-7);
            EXPECT_GE(image.y() / image.w(), -1e-7);
            EXPECT_LE(image.y() / image.w(), map->crop.map.height + 1e-7);
            EXPECT_GE(image.z() / image.w(), -1e-9);
            EXPECT_LE(image.z() / image.w(), 1.0 + 1e-9);
        }
    }
}

TEST(PlaneOptimalProperty, DepthGrowsAwayFromTheLightAlongEveryNeededRay) {
    std::mt19937_64 rng(4242);
    for (int i = 0; i < kConfigurations / 10; ++i) {
        const Configuration c = RandomConfiguration(rng);
        PlaneMapRequest request;
        request.input = c.Input();
        request.bounds = c.bounds;
        const auto map = SolvePlaneMap(request);
        ASSERT_TRUE(map.ok()) << i << ": " << map.error().Message();
        const Mat4& m = map->crop.map.matrix;
        const Vec4& l = map->uncropped.light;
        for (const Vec3& p : map->needed_polygon) {
            // Points on the ray from the light to p, at increasing distance from the light.
            double previous = -std::numeric_limits<double>::infinity();
            for (double t : {0.3, 0.5, 0.7, 0.9, 1.0}) {
                const Vec3 x = l.w() == 0.0 ? Vec3(p + (1.0 - t) * 5.0 * l.head<3>())
                                            : Vec3(l.head<3>() + t * (p - l.head<3>()));
                const Vec4 image = m * Point(x);
                ASSERT_GT(image.w(), 0.0) << "a point of a needed ray is behind the light image";
                const double z = image.z() / image.w();
                EXPECT_GT(z, previous) << "configuration " << i << " t " << t;
                previous = z;
            }
        }
    }
}

}  // namespace
}  // namespace lixel
