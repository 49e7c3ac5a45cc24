// Tests for baselines.h: uniform, PSM and LiSPSM maps fitted to one extent hull.
#include <gtest/gtest.h>
#include <lixel/solver/baselines.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "map_checks.h"
#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

constexpr BaselineMethod kMethods[] = {BaselineMethod::kUniform, BaselineMethod::kPsm,
                                       BaselineMethod::kLispsm};

BaselineInput InputOf(const testing::Configuration& c, std::int64_t budget) {
    return {c.viewer, c.viewport, c.light, budget};
}

// A random configuration; half the point lights are moved out of the bounds (some behind the
// viewer), a quarter of the scenes are scaled by 1e-6 or 1e6.
testing::Configuration BaselineConfiguration(std::mt19937_64& rng) {
    testing::Configuration c = testing::RandomConfiguration(rng);
    const double distance = (c.target - c.eye).norm();
    if (c.light.w() != 0.0 && std::bernoulli_distribution(0.5)(rng)) {
        c.light = Point(c.target + RandomUnit(rng) * Uniform(rng, 4.0, 60.0) * distance);
    }
    if (std::bernoulli_distribution(0.25)(rng)) {
        const double s = std::bernoulli_distribution(0.5)(rng) ? 1e-6 : 1e6;
        Mat4 unscale = Mat4::Identity();
        unscale.topLeftCorner<3, 3>() /= s;
        c.viewer = c.viewer * unscale;
        c.bounds = {c.bounds.min * s, c.bounds.max * s};
        c.eye *= s;
        c.target *= s;
        if (c.light.w() != 0.0) c.light = Point(c.light.head<3>() * s);
    }
    return c;
}

// A point inside H: a random convex combination of its vertices.
Vec3 PointInHull(std::mt19937_64& rng, const ExtentHull& h) {
    Vec3 p = Vec3::Zero();
    double total = 0.0;
    for (const Vec4& v : h.ray_points) {
        const double weight = Uniform(rng, 0.0, 1.0);
        p += weight * v.head<3>();
        total += weight;
    }
    return p / total;
}

TEST(Baselines, EveryMethodHoldsTheHullWithinTheBudget) {
    std::mt19937_64 rng(9001);
    int configurations = 0;
    int lispsm_warped = 0;
    int psm_inverted = 0;
    for (int i = 0; i < 1600 && configurations < 1200; ++i) {
        const testing::Configuration c = BaselineConfiguration(rng);
        const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
        if (!hull.ok() || hull->light_inside) continue;
        ++configurations;
        const std::int64_t budget = static_cast<std::int64_t>(std::pow(2.0, Uniform(rng, 8, 28)));
        for (BaselineMethod method : kMethods) {
            const auto fit = FitBaseline(method, InputOf(c, budget), *hull);
            ASSERT_TRUE(fit.ok()) << BaselineName(method) << " config " << i << ": "
                                  << fit.error().Message();
            ASSERT_TRUE(testing::MapHoldsPoints(fit->map, hull->ray_points))
                << BaselineName(method) << " config " << i;
            EXPECT_TRUE(testing::LightAtInfinity(fit->map, hull->light))
                << BaselineName(method) << " config " << i;
            EXPECT_LE(static_cast<std::int64_t>(fit->map.width) * fit->map.height, budget);
            EXPECT_TRUE(testing::DepthGrowsAlongRay(fit->map, hull->light, PointInHull(rng, *hull),
                                                    c.bounds.Diagonal()))
                << BaselineName(method) << " config " << i;
            EXPECT_EQ(fit->info.requested, method);
            EXPECT_EQ(fit->info.used == method, fit->info.fallback_reason.empty());
            if (method == BaselineMethod::kLispsm && fit->info.used == method) ++lispsm_warped;
            if (method == BaselineMethod::kPsm && fit->info.light_inverted_in_post_perspective) {
                ++psm_inverted;
            }
        }
    }
    EXPECT_GE(configurations, 1000);
    EXPECT_GE(lispsm_warped, configurations / 2);  // fallbacks are the exception
    EXPECT_GT(psm_inverted, 0);                    // lights behind the viewer were exercised
}

// The paper's floor/wall room (test_scenes) with a directional light.
testing::Configuration Room(const Vec4& light) {
    testing::Configuration c = testing::FloorWallConfiguration();
    c.light = light;
    return c;
}

TEST(Baselines, LispsmFallsBackWhenViewIsParallelToTheLight) {
    testing::Configuration c = Room(Vec4::Zero());
    const Vec3 forward = (c.target - c.eye).normalized();
    // Light straight behind the viewer, and straight ahead of it.
    for (const Vec3& toward : {Vec3(-forward), forward}) {
        c.light = Direction(toward);
        const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
        ASSERT_TRUE(hull.ok()) << hull.error().Message();
        const auto fit = FitLispsmMap(InputOf(c, 1 << 20), *hull);
        ASSERT_TRUE(fit.ok()) << fit.error().Message();
        EXPECT_EQ(fit->info.used, BaselineMethod::kUniform);
        EXPECT_NE(fit->info.fallback_reason.find("parallel"), std::string::npos);
        EXPECT_LT(fit->info.sin_gamma, kLispsmMinSinGamma);
        EXPECT_TRUE(testing::MapHoldsPoints(fit->map, hull->ray_points));
        // The fallback is the uniform map itself.
        const auto uniform = FitUniformMap(InputOf(c, 1 << 20), *hull);
        ASSERT_TRUE(uniform.ok());
        EXPECT_TRUE(fit->map.matrix.isApprox(uniform->map.matrix, 1e-14));
    }
}

TEST(Baselines, LispsmUsesTheOptimalNearDistance) {
    // Light from above, view along -z tilted down: gamma is the angle between the view
    // direction and the light, n_opt = (z_n + sqrt(z_n z_f)) / sin(gamma) (Wimmer et al. 2004).
    testing::Configuration c = Room(Direction(Vec3(0.2, 1.0, 0.1)));
    const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    ASSERT_TRUE(hull.ok());
    const auto fit = FitLispsmMap(InputOf(c, 1 << 20), *hull);
    ASSERT_TRUE(fit.ok()) << fit.error().Message();
    ASSERT_EQ(fit->info.used, BaselineMethod::kLispsm);
    const Vec3 forward = (c.target - c.eye).normalized();
    const Vec3 d = c.light.head<3>().normalized();
    EXPECT_NEAR(fit->info.sin_gamma, forward.cross(d).norm(), 1e-12);
    // z_n, z_f: V's depth range along the view direction.
    double z_n = 1e300, z_f = -1e300;
    for (const Vec3& v : hull->view_volume.vertices()) {
        z_n = std::min(z_n, forward.dot(v - c.eye));
        z_f = std::max(z_f, forward.dot(v - c.eye));
    }
    EXPECT_NEAR(fit->info.z_near, z_n, 1e-9);
    EXPECT_NEAR(fit->info.z_far, z_f, 1e-9);
    EXPECT_NEAR(fit->info.n_opt, (z_n + std::sqrt(z_n * z_f)) / fit->info.sin_gamma, 1e-9);
    EXPECT_EQ(fit->info.warp_near, fit->info.n_opt);
    // The warp puts more lixels near the viewer than far away, unlike the uniform map: compare
    // lixels per world unit on the floor near and far along the view direction.
    const auto uniform = FitUniformMap(InputOf(c, 1 << 20), *hull);
    ASSERT_TRUE(uniform.ok());
    auto density = [&](const LightMap& m, const Vec3& p) {
        const Vec3 step(0.0, 0.0, -0.01);
        return (LixelOf(m, Point(p + step)) - LixelOf(m, Point(p))).norm() / 0.01;
    };
    const Vec3 near_floor(0.0, 0.0, 6.0);
    const Vec3 far_floor(0.0, 0.0, -4.0);
    const double lispsm_ratio = density(fit->map, near_floor) / density(fit->map, far_floor);
    const double uniform_ratio =
        density(uniform->map, near_floor) / density(uniform->map, far_floor);
    EXPECT_GT(lispsm_ratio, 1.5 * uniform_ratio);
}

// Lloyd et al.'s aliasing m at the point of plane y = 0 seen at pixel (x, y): pixels per lixel
// along the plane's worst direction, 1 / sigma_min of d(lixel)/d(pixel) on the plane (as
// server/eval's aliasing report computes it). Lower is better; NaN when the pixel misses the
// plane or the map does not image the point.
double FloorAliasing(const Mat4& pixel_matrix, const LightMap& map, double x, double y) {
    const Mat4 unproject = pixel_matrix.inverse();
    Vec4 a = unproject * Vec4(x, y, kClipDepthNear, 1.0);
    Vec4 b = unproject * Vec4(x, y, kClipDepthFar, 1.0);
    a /= a.w();
    b /= b.w();
    if (!(a.y() * b.y() < 0.0)) return std::numeric_limits<double>::quiet_NaN();
    const Vec4 point = a + (a.y() / (a.y() - b.y())) * (b - a);
    // d(image)/d(u, v) along the floor's tangents x and z.
    auto derivative = [&](const Mat4& m, Mat2& d) {
        const Vec4 p = m * point;
        if (!(p.w() > 0.0)) return false;
        const Vec4 tangents[2] = {m.col(0), m.col(2)};
        for (int k = 0; k < 2; ++k) {
            d(0, k) = (tangents[k].x() * p.w() - p.x() * tangents[k].w()) / (p.w() * p.w());
            d(1, k) = (tangents[k].y() * p.w() - p.y() * tangents[k].w()) / (p.w() * p.w());
        }
        return true;
    };
    Mat2 d_pixel, d_lixel;
    if (!derivative(pixel_matrix, d_pixel) || !derivative(map.matrix, d_lixel)) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const Mat2 jacobian = d_lixel * d_pixel.inverse();
    return 1.0 / Eigen::JacobiSVD<Mat2>(jacobian).singularValues()(1);
}

// LiSPSM's purpose: on receivers near the viewer it samples far better than the uniform map
// when the light is perpendicular to the view. A viewer 2 units above a 100-unit-deep floor,
// looking almost level, the eye inside the scene bounds (so V starts at the camera's near
// plane, z_n = 0.1, z_f = 100); at the bottom of the viewport the uniform map gives m ~ 52,
// LiSPSM ~ 4 (512^2 lixels, 1024^2 pixels).
TEST(Baselines, LispsmBeatsUniformNearTheViewerWithAPerpendicularLight) {
    const Vec3 eye(0.0, 2.0, 0.0);
    const Viewport viewport{1024, 1024};
    const Mat4 viewer = Perspective(60.0 * std::numbers::pi / 180.0, 1.0, 0.1, 100.0) *
                        LookAt(eye, Vec3(0.0, 1.5, -10.0), Vec3::UnitY());
    const Mat4 pixels = PixelMatrix(viewer, viewport);
    const Aabb bounds{Vec3(-50.0, 0.0, -100.0), Vec3(50.0, 10.0, 5.0)};
    constexpr double kBetter = 4.0;  // measured: 12.7 (directional), 11.1 (point)
    // Straight overhead, as a direction and as a distant point light (warped in its
    // post-perspective space).
    for (const Vec4& light : {Direction(Vec3(0.0, 1.0, 0.0)), Point(Vec3(0.0, 200.0, -50.0))}) {
        const auto hull = ComputeExtentHull(viewer, light, bounds);
        ASSERT_TRUE(hull.ok()) << hull.error().Message();
        const BaselineInput input{viewer, viewport, light, 512 * 512};
        const auto uniform = FitUniformMap(input, *hull);
        const auto lispsm = FitLispsmMap(input, *hull);
        ASSERT_TRUE(uniform.ok() && lispsm.ok());
        ASSERT_EQ(lispsm->info.used, BaselineMethod::kLispsm) << lispsm->info.fallback_reason;
        EXPECT_GT(lispsm->info.sin_gamma, 0.99);
        // The floor 2% of the viewport above its bottom edge (about 3 units ahead of the eye).
        const double x = 0.5 * viewport.width, y = 0.02 * viewport.height;
        const double m_uniform = FloorAliasing(pixels, uniform->map, x, y);
        const double m_lispsm = FloorAliasing(pixels, lispsm->map, x, y);
        EXPECT_LT(kBetter * m_lispsm, m_uniform) << "light " << light.transpose();
    }
}

// The floor/wall room with its point light ahead of and above the viewer: with the camera's
// near plane at 0.1 inside the scene bounds, V (and so LiSPSM's z_n and PSM's near plane)
// starts 0.1 from the eye, though the nearest visible floor is ~3.8 away, and both warps spend
// most of the map on that empty space. With the near plane pulled up to the receivers (3.0),
// the same construction beats the uniform map on the nearest floor (measured m: LiSPSM 5.0,
// PSM 3.7, uniform 6.7), so the warps point the right way for this light.
TEST(Baselines, WarpsBeatUniformOnTheNearFloorWhenTheNearPlaneIsAtTheReceivers) {
    testing::Configuration c = testing::FloorWallConfiguration();
    c.viewer = Perspective(60.0 * std::numbers::pi / 180.0, 1.0, 3.0, 100.0) *
               LookAt(c.eye, c.target, Vec3::UnitY());
    const Mat4 pixels = PixelMatrix(c.viewer, c.viewport);
    const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    ASSERT_TRUE(hull.ok()) << hull.error().Message();
    const auto uniform = FitUniformMap(InputOf(c, 512 * 512), *hull);
    ASSERT_TRUE(uniform.ok());
    const double x = 0.5 * c.viewport.width, y = 0.02 * c.viewport.height;
    const double m_uniform = FloorAliasing(pixels, uniform->map, x, y);
    for (BaselineMethod method : {BaselineMethod::kLispsm, BaselineMethod::kPsm}) {
        const auto fit = FitBaseline(method, InputOf(c, 512 * 512), *hull);
        ASSERT_TRUE(fit.ok()) << fit.error().Message();
        ASSERT_EQ(fit->info.used, method) << fit->info.fallback_reason;
        EXPECT_LT(1.2 * FloorAliasing(pixels, fit->map, x, y), m_uniform) << BaselineName(method);
    }
}

TEST(Baselines, PsmSlidesBackForCastersBehindTheViewer) {
    // Light behind and above the viewer, outside the bounds: H reaches behind the eye up to
    // the bounds, so the virtual camera must slide back, and the light lands behind the
    // virtual eye in post-perspective space.
    testing::Configuration c = testing::FloorWallConfiguration();
    c.light = Point(Vec3(0.0, 7.0, 14.0));
    const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    ASSERT_TRUE(hull.ok()) << hull.error().Message();
    ASSERT_FALSE(hull->light_inside);
    const auto fit = FitPsmMap(InputOf(c, 1 << 20), *hull);
    ASSERT_TRUE(fit.ok()) << fit.error().Message();
    EXPECT_GT(fit->info.slide_back, 0.0);
    EXPECT_TRUE(fit->info.light_inverted_in_post_perspective);
    EXPECT_TRUE(testing::MapHoldsPoints(fit->map, hull->ray_points));
    // A light in front of the viewer needs no slide-back when H stays in front of the eye.
    c.light = Point(Vec3(0.0, 7.0, -4.0));
    const auto front_hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    ASSERT_TRUE(front_hull.ok());
    const auto front = FitPsmMap(InputOf(c, 1 << 20), *front_hull);
    ASSERT_TRUE(front.ok()) << front.error().Message();
    EXPECT_FALSE(front->info.light_inverted_in_post_perspective);
    EXPECT_EQ(front->info.slide_back, 0.0);
    EXPECT_TRUE(testing::MapHoldsPoints(front->map, front_hull->ray_points));
}

TEST(Baselines, PointLightLispsmWarpsInTheLightsPostPerspectiveSpace) {
    testing::Configuration c = testing::FloorWallConfiguration();  // light (4, 9, 3)
    const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    ASSERT_TRUE(hull.ok());
    const auto fit = FitLispsmMap(InputOf(c, 1 << 20), *hull);
    ASSERT_TRUE(fit.ok()) << fit.error().Message();
    EXPECT_EQ(fit->info.used, BaselineMethod::kLispsm) << fit->info.fallback_reason;
    EXPECT_GT(fit->info.n_opt, 0.0);
    const auto uniform = FitUniformMap(InputOf(c, 1 << 20), *hull);
    ASSERT_TRUE(uniform.ok());
    EXPECT_FALSE(fit->map.matrix.isApprox(uniform->map.matrix, 1e-6));
}

TEST(Baselines, BadInputIsRefusedNamingTheField) {
    const testing::Configuration c = testing::FloorWallConfiguration();
    const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    ASSERT_TRUE(hull.ok());
    for (BaselineMethod method : kMethods) {
        BaselineInput in = InputOf(c, 0);
        EXPECT_EQ(FitBaseline(method, in, *hull).error().field, "lixel_budget");
        in = InputOf(c, 1024);
        in.light = Point(Vec3(1, 2, 3));
        EXPECT_EQ(FitBaseline(method, in, *hull).error().field, "hull");
        in = InputOf(c, 1024);
        in.viewport.width = 0;
        EXPECT_EQ(FitBaseline(method, in, *hull).error().field, "viewport.width");
        in = InputOf(c, 1024);
        in.viewer(0, 0) = std::numeric_limits<double>::infinity();
        EXPECT_EQ(FitBaseline(method, in, *hull).error().field, "viewer[0][0]");
        // A light inside V: one map cannot hold C_tot.
        testing::Configuration inside = c;
        inside.light = Point(Vec3(0.0, 1.0, 0.0));
        const auto inside_hull = ComputeExtentHull(inside.viewer, inside.light, inside.bounds);
        ASSERT_TRUE(inside_hull.ok());
        ASSERT_TRUE(inside_hull->light_inside);
        const auto refused = FitBaseline(method, InputOf(inside, 1024), *inside_hull);
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(refused.error().field, "hull");
    }
}

}  // namespace
}  // namespace lixel
