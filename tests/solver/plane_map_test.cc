// Tests for plane_map.h: the paper's floor/wall configuration end to end, diagnostics, and the
// floor map's twist that puts the floor/wall line horizontal (Chong & Gortler §3).
#include <gtest/gtest.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/polygon.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Configuration;
using testing::FloorWallConfiguration;

// The plane map request of a configuration: its input, with its bounds.
PlaneMapRequest RequestOf(const Configuration& c) {
    PlaneMapRequest request;
    request.input = c.Input();
    request.bounds = c.bounds;
    return request;
}

TEST(PlaneMap, FloorOfTheFloorWallRoomHasOneLixelPerPixel) {
    const Configuration c = FloorWallConfiguration();
    PlaneMapRequest request = RequestOf(c);
    const auto map = SolvePlaneMap(request);
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_LE(map->diagnostics.residual_lixels, 1e-9);
    EXPECT_LE(map->diagnostics.residual_lixels_float, 0.01);
    EXPECT_TRUE(map->diagnostics.horizon_in_view);  // the view's top edge is 16° above level
    EXPECT_EQ(map->diagnostics.sign, 1);
    EXPECT_GT(map->diagnostics.depth_resolution, 0.0);
    // World units per float depth step at the floor, with depth fitted to the whole room in the
    // floor's rays (the bounds reach within one unit of the light): under 1e-3 of the room.
    EXPECT_LT(map->diagnostics.depth_resolution, 1e-3 * c.bounds.Diagonal());
    // The floor fills part of the 1024^2 view, so its map is no larger than the view.
    EXPECT_LE(map->crop.map.width, 1024);
    EXPECT_LE(map->crop.map.height, 1024);
}

// Maps store depth reversed, 1 - z (light_map.h), and the diagnostics report the step of what
// is stored. Against z stored as it is, computed here from the matrix: ulp(z) / |dz/ds| along
// the light ray at the floor's corner farthest from the light. Measured in the floor/wall room:
// 1.9e-6 against 3.1e-5 world units there (16x), 7.3e-7 against 7.7e-6 at the nearest (11x).
TEST(PlaneMap, ReversedDepthResolvesTheFloorFinerThanForwardDepth) {
    const Configuration c = FloorWallConfiguration();
    PlaneMapRequest request = RequestOf(c);
    const auto map = SolvePlaneMap(request);
    ASSERT_TRUE(map.ok()) << map.error().Message();
    const LightMap& m = map->crop.map;
    const Vec3 light = c.light.head<3>();
    auto forward_step = [&](const Vec3& s) {
        const Vec4 x = Point(s);
        const Vec3 d = (s - light).normalized();
        const Vec4 dir(d.x(), d.y(), d.z(), 0.0);
        const double q = m.matrix.row(3).dot(x);
        const double z = m.matrix.row(2).dot(x) / q;
        const double dz = (m.matrix.row(2).dot(dir) * q - m.matrix.row(2).dot(x) *
                                                                m.matrix.row(3).dot(dir)) /
                          (q * q);
        const float f = static_cast<float>(z);
        return (static_cast<double>(std::nextafter(f, 2.0f)) - f) / std::abs(dz);
    };
    double farthest = 0.0;
    Vec3 far_point = Vec3::Zero();
    for (const Vec3& v : map->needed_polygon) {
        if ((v - light).norm() > farthest) {
            farthest = (v - light).norm();
            far_point = v;
        }
    }
    const SolveDiagnostics& d = map->diagnostics;
    EXPECT_LT(10.0 * d.depth_step_farthest, forward_step(far_point))
        << d.depth_step_farthest << " at " << far_point.transpose();
    EXPECT_LT(10.0 * d.depth_resolution, forward_step(far_point));
    std::printf("[ measured ] floor: stored 1 - z step %.3g, z step %.3g at the farthest corner\n",
                d.depth_step_farthest, forward_step(far_point));
}

TEST(PlaneMap, FloorTwistPutsTheFloorWallLineHorizontalAndTheWallAboveTheMap) {
    const Configuration c = FloorWallConfiguration();
    PlaneMapRequest request = RequestOf(c);
    // The floor below the floor/wall line z = -5 (paper §3): the polygon stops at the wall.
    const Vec4 wall(0, 0, 1, 5);  // z >= -5 is the room's side
    request.needed_polygon = ClipPolygon(VisiblePlanePolygon(c.viewer, c.plane, c.bounds), wall);
    request.crop.twist = Twist::kLineHorizontal;
    request.crop.line_a = Vec4(-10, 0, -5, 1);
    request.crop.line_b = Vec4(10, 0, -5, 1);
    const auto map = SolvePlaneMap(request);
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_LE(map->diagnostics.residual_lixels, 1e-9);
    const LightMap& m = map->crop.map;
    // Points on the line share y, and lie on or above the map's top edge.
    const Vec2 a = LixelOf(m, request.crop.line_a);
    const Vec2 b = LixelOf(m, Vec4(3, 0, -5, 1));
    EXPECT_NEAR(a.y(), b.y(), 1e-9);
    EXPECT_GE(a.y(), m.height - 1.0);
    // Any point of the wall above the floor images above the line: out of the floor map's bounds.
    for (double y : {0.5, 2.0, 6.0}) {
        for (double x : {-4.0, 0.0, 4.0}) {
            EXPECT_GT(LixelOf(m, Vec4(x, y, -5, 1)).y(), a.y()) << x << ", " << y;
        }
    }
}

TEST(PlaneMap, BudgetBelowOnePerPixelGivesOneReportedScale) {
    const Configuration c = FloorWallConfiguration();
    PlaneMapRequest request = RequestOf(c);
    request.crop.lixel_budget = 350 * 350;  // the paper's per-plane allocation
    const auto map = SolvePlaneMap(request);
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_LE(static_cast<long>(map->crop.map.width) * map->crop.map.height, 350L * 350L);
    EXPECT_LT(map->crop.scale, 1.0);
    // The residual is measured against A_l * pixel, so it stays exact at any scale.
    EXPECT_LE(map->diagnostics.residual_lixels, 1e-9);
}

TEST(PlaneMap, FootprintScaleIsMeasuredApartFromTheCropOverRandomViews) {
    // The composite pixel -> plane point -> lixel is the affine A_l (paper 004 §2): both singular
    // values of its Jacobian equal the crop's scale, up to the rounding of half-pixel central
    // differences through the double matrices.
    std::mt19937_64 rng(4417);
    int solved = 0;
    double worst = 0.0;
    for (int i = 0; i < 500; ++i) {
        const Configuration c = testing::RandomConfiguration(rng);
        PlaneMapRequest request;
        request.input = c.Input();
        request.bounds = c.bounds;
        request.crop.scale = i % 2 == 0 ? 1.0 : 0.37;
        const auto map = SolvePlaneMap(request);
        if (!map.ok()) continue;
        ++solved;
        const SolveDiagnostics& d = map->diagnostics;
        const double scale = map->crop.scale;
        const double error = std::max(std::abs(d.lixels_per_pixel_min - scale),
                                      std::abs(d.lixels_per_pixel_max - scale)) /
                             scale;
        worst = std::max(worst, error);
        EXPECT_LE(error, 1e-8) << "configuration " << i << ": " << d.lixels_per_pixel_min << " .. "
                               << d.lixels_per_pixel_max << " for scale " << scale;
        // The steps at the two ends are samples of the worst one.
        EXPECT_GT(d.depth_step_nearest, 0.0) << "configuration " << i;
        EXPECT_GT(d.depth_step_farthest, 0.0) << "configuration " << i;
        EXPECT_LE(d.depth_step_nearest, d.depth_resolution) << "configuration " << i;
        EXPECT_LE(d.depth_step_farthest, d.depth_resolution) << "configuration " << i;
    }
    std::printf("[ measured ] %d solves: lixels per pixel within %.2g of the scale (relative)\n",
                solved, worst);
    EXPECT_GT(solved, 400);
}

// footprint_diagnostics = false (the scheduler's first solve of a plane, whose figures the
// second replaces) leaves out the lixels per pixel and nothing else: the same matrix, crop,
// residuals, depth steps and samples, and the same refusals, over random configurations.
TEST(PlaneMap, WithoutFootprintDiagnosticsOnlyTheLixelsPerPixelAreLeftOut) {
    std::mt19937_64 rng(4418);
    int solved = 0;
    for (int i = 0; i < 300; ++i) {
        const Configuration c = testing::RandomConfiguration(rng);
        PlaneMapRequest request;
        request.input = c.Input();
        request.bounds = c.bounds;
        const auto full = SolvePlaneMap(request);
        request.footprint_diagnostics = false;
        const auto bare = SolvePlaneMap(request);
        ASSERT_EQ(full.ok(), bare.ok()) << "configuration " << i;
        if (!full.ok()) {
            EXPECT_EQ(full.error().Message(), bare.error().Message());
            continue;
        }
        ++solved;
        EXPECT_EQ(full->crop.map.matrix, bare->crop.map.matrix) << "configuration " << i;
        EXPECT_EQ(full->crop.map.width, bare->crop.map.width);
        EXPECT_EQ(full->crop.map.height, bare->crop.map.height);
        const SolveDiagnostics& f = full->diagnostics;
        const SolveDiagnostics& b = bare->diagnostics;
        EXPECT_EQ(f.residual_lixels, b.residual_lixels);
        EXPECT_EQ(f.residual_lixels_float, b.residual_lixels_float);
        EXPECT_EQ(f.conditioning, b.conditioning);
        EXPECT_EQ(f.depth_resolution, b.depth_resolution);
        EXPECT_EQ(f.depth_step_nearest, b.depth_step_nearest);
        EXPECT_EQ(f.depth_step_farthest, b.depth_step_farthest);
        EXPECT_EQ(f.samples, b.samples);
        EXPECT_GT(f.lixels_per_pixel_max, 0.0);
        EXPECT_EQ(b.lixels_per_pixel_min, 0.0);
        EXPECT_EQ(b.lixels_per_pixel_max, 0.0);
    }
    EXPECT_GT(solved, 200);
}

TEST(PlaneMap, AWrongScaleIsSeenByTheFootprint) {
    const Configuration c = FloorWallConfiguration();
    PlaneMapRequest request = RequestOf(c);
    const auto map = SolvePlaneMap(request);
    ASSERT_TRUE(map.ok()) << map.error().Message();
    // A map 1 % too fine: rows x and y scaled about the image origin.
    LightMap wrong = map->crop.map;
    wrong.matrix.row(0) *= 1.01;
    wrong.matrix.row(1) *= 1.01;
    const Vec2 centre(512.0, 300.0);
    auto right = LixelsPerPixel(c.viewer, c.viewport, c.plane, map->crop.map, centre);
    auto off = LixelsPerPixel(c.viewer, c.viewport, c.plane, wrong, centre);
    ASSERT_TRUE(right.ok() && off.ok());
    EXPECT_NEAR(right->x(), 1.0, 1e-9);
    EXPECT_NEAR(right->y(), 1.0, 1e-9);
    EXPECT_NEAR(off->x(), 1.01, 1e-9);
    EXPECT_NEAR(off->y(), 1.01, 1e-9);
    // Against the pixels above the horizon the ray meets the floor behind the viewer.
    EXPECT_FALSE(LixelsPerPixel(c.viewer, c.viewport, c.plane, map->crop.map,
                                Vec2(512.0, 1023.0))
                     .ok());
}

}  // namespace
}  // namespace lixel
