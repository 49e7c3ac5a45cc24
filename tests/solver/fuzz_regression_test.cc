// Solver fuzz regressions: inputs fuzz/fuzz_solver and fuzz/fuzz_scheduler crashed on (ASan,
// UBSan or a broken contract), reduced to their essentials. Each must be refused or answered
// with a finite result, never undefined behaviour.
#include <lixel/solver/camera.h>
#include <lixel/solver/crop.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace lixel {
namespace {

// Needed rays imaged 1e200 lixels apart: the integer rectangle's side used to be converted to
// int64 out of range (crop.cc IntegerRectangle). Now the scale shrinks it into the limits.
TEST(FuzzRegression, CropOfImagesFarApartShrinksIntoTheLimits) {
    const std::vector<Vec4> needed = {Point(Vec3(0.0, 0.0, 0.0)), Point(Vec3(1e200, 0.0, 0.0)),
                                      Point(Vec3(0.0, 1e126, 0.0))};
    for (Twist twist : {Twist::kNone, Twist::kMinimizeArea}) {
        CropOptions options;
        options.twist = twist;
        const auto crop = CropToNeededRays(Mat4::Identity(), needed, options);
        ASSERT_TRUE(crop.ok()) << crop.error().Message();
        EXPECT_TRUE(crop->map.matrix.allFinite());
        EXPECT_GE(crop->map.width, 1);
        EXPECT_LE(crop->map.width, kMaxImageSide);
        EXPECT_GE(crop->map.height, 1);
        EXPECT_LE(crop->map.height, kMaxImageSide);
        EXPECT_GT(crop->scale, 0.0);
    }
}

// Images at -1e308 and +1e308: their spread is past the range of double and is refused.
TEST(FuzzRegression, CropOfImagesSpreadPastDoubleIsRefused) {
    const std::vector<Vec4> needed = {Point(Vec3(-1e308, 0.0, 0.0)), Point(Vec3(1e308, 0.0, 0.0))};
    const auto crop = CropToNeededRays(Mat4::Identity(), needed, CropOptions{});
    ASSERT_FALSE(crop.ok());
    EXPECT_EQ(crop.error().field, "needed_points");
}

// A needed polygon off its plane with the point light on one of its vertices: the solve was ok,
// but the float GL projection of that vertex divides by zero, and the diagnostics carried
// residual_lixels_float = inf to the wire. Now refused, naming the polygon.
TEST(FuzzRegression, PlaneMapWhoseFloatProjectionOverflowsIsRefused) {
    PlaneMapRequest request;
    // Exact doubles (hexadecimal) as the fuzzer built them: a look-at perspective viewer.
    request.input.viewer << 0.0, 0.0, -0x1.08faea9a2e61fp+1, 0x1.5bc953ea5ce09p+2,  //
        0.0, 0x1.08faea9a2e61fp+1, 0.0, -0x1.5bc953ea5ce09p+2,                      //
        -0x1.00419a0290041p+0, 0.0, 0.0, 0x1.b3a2b9045b3a2p+1,                      //
        -1.0, 0.0, 0.0, 3.5;
    request.input.viewport = {30, 30};
    request.input.light = Vec4(2.625, 2.625, 2.625, 1.0);
    request.input.plane = Vec4(2.625, 2.625, 1.875, 1.875);
    request.needed_polygon = {Vec3(1.875, 2.625, 2.625), Vec3(2.625, 2.625, 2.625),
                              Vec3(2.625, 2.625, -1.625)};
    request.bounds = Aabb{Vec3::Constant(2.625), Vec3::Constant(5.25)};
    const auto map = SolvePlaneMap(request);
    ASSERT_FALSE(map.ok()) << map->diagnostics.residual_lixels_float;
    EXPECT_EQ(map.error().field, "needed_polygon") << map.error().Message();
}

// A point light at z = 2.2e307, finite but so far that the cube face maps around it overflowed
// to inf entries in an ok() plan. Now refused, or answered with finite maps.
TEST(FuzzRegression, PlanWithLightNearDoubleMaxHasNoInfiniteMaps) {
    Mesh cube;
    for (int i = 0; i < 8; ++i) {
        cube.positions.emplace_back(static_cast<float>(i & 1), static_cast<float>((i >> 1) & 1),
                                    static_cast<float>((i >> 2) & 1));
    }
    cube.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                    2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    cube.closed = true;
    PlanRequest request;
    request.viewer << -0.667985806910591, 0.0, -1.9594250336044, 0.0,                      //
        0.672968182408627, 1.94423027030086, -0.229420971275668, -2.87292045889233e-16,  //
        -0.889824063269214, 0.34379566080856, 0.303349112478141, 6.09327761299529,       //
        -0.888934239205945, 0.343451865147752, 0.303045763365663, 6.18718433538229;
    request.viewport = {16384, 16384};
    request.light = Vec4(1.06787078841168e-288, -2.79490533959263e+179, 2.20834115152208e+307, 1.0);
    for (int i = 0; i < 3; ++i) {
        request.objects.push_back(SceneObject{"cube", cube.Bounds(), &cube, true});
    }
    const auto plan = PlanShadowMaps(request);
    if (!plan.ok()) {
        EXPECT_EQ(plan.error().field, "request") << plan.error().Message();
        return;
    }
    for (const PlannedMap& m : plan->maps) {
        EXPECT_TRUE(m.map.matrix.allFinite()) << m.name;
        EXPECT_TRUE(std::isfinite(m.expected_pixels)) << m.name;
    }
}

// A viewer whose matrix is ill-conditioned (condition number about 1e8) over a floor with a box:
// the pixel estimate's tile proofs are off for it, and its per-ray screen culls must read the
// proofs' rectangles only when they are on (fuzz_scheduler under UBSan: a reference into an
// empty vector).
TEST(FuzzRegression, PlanWithAnIllConditionedViewerEstimatesPixelsWithoutTileProofs) {
    PlanRequest request;
    request.viewer = Perspective(1.0, 1.0, 0.1, 100.0) *
                     LookAt(Vec3(0, 6, 6), Vec3(0, 0, 0), Vec3::UnitY());
    request.viewer.row(0) *= 1e4;
    request.viewer.row(1) *= 1e-4;
    request.viewport = {256, 256};
    request.light = Point(Vec3(3.0, 8.0, 2.0));
    request.scene_bounds = Aabb{Vec3(-5, -1, -5), Vec3(5, 3, 5)};
    request.planes = {PlaneOfInterest{"floor", Vec4(0, 1, 0, 0), {}}};
    request.objects = {SceneObject{"box", Aabb{Vec3(-1, 0, -1), Vec3(1, 2, 1)}, nullptr, true},
                       SceneObject{"floor", Aabb{Vec3(-5, -1, -5), Vec3(5, 0, 5)}, nullptr, true}};
    request.lixel_budget = 256 * 256;
    const auto plan = PlanShadowMaps(request);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    for (const PlannedMap& m : plan->maps) {
        EXPECT_TRUE(m.map.matrix.allFinite()) << m.name;
        EXPECT_TRUE(std::isfinite(m.expected_pixels)) << m.name;
    }
}

// Points whose light images are each finite but 2e308 apart: the rectangle's aspect was
// inf / inf, and the map size a NaN converted to an integer (fuzz_solver under UBSan).
TEST(FuzzRegression, FrustumOfImagesFurtherApartThanADoubleIsRefused) {
    const Mat4 prelim = Mat4::Identity();  // rows 0, 1, 3 are planes through the light at w = 0
    // Images at (-1e308, -1e308) and (1e308, 1e308): q = 1e-308 > 0, x = y = +-1 / q.
    const std::vector<Vec4> points = {Vec4(-1.0, -1.0, 0.0, 1e-308), Vec4(1.0, 1.0, 0.0, 1e-308)};
    MapSize size;
    size.lixel_budget = 1024;
    const auto map = FitImageRectangle(prelim, Vec4(0, 0, 1, 0), points, size);
    ASSERT_FALSE(map.ok());
    EXPECT_EQ(map.error().field, "points") << map.error().Message();
}

// A fallback FitWithinSide leaves at the GL maximum side (16384, a sliver under a directional
// light with an unbounded budget): its guard band must not take it past the maximum
// (fuzz_scheduler: a 16388 x 2843 map broke the contract). The band narrows instead.
TEST(FuzzRegression, GuardBandNeverTakesAMapPastTheMaximumSide) {
    PlanRequest request;
    request.viewer << -0x1p+2, 0x1.1p+1, -0x1.a8p+2, 0x1.3p+2,  //
        0x1.4p+0, -0x1p+0, 0x1p+0, 0x0p+0,                        //
        0x0.0000000000001p-1022, 0x0p+0, 0x1.fp+1, 0x0p+0,        //
        -0x1.7p+2, 0x0p+0, 0x1.0cp+3, -0x1.8p-1;
    request.viewport = {3065, 5420};
    request.light = Vec4(0.0, 0x1.ap+2, 0x1.cp+0, 0.0);
    request.objects = {
        SceneObject{"a", Aabb{Vec3(-0x1.a8p+2, -0x1.8p+1, 0.0), Vec3(-0x1.68p+2, -0x1p+1, 1.0)},
                    nullptr, true},
        SceneObject{"b", Aabb{Vec3(0, 0, 0), Vec3(1, 1, 1)}, nullptr, true},
        SceneObject{"c", Aabb{Vec3(0, 0, 0), Vec3(1, 1, 1)}, nullptr, false}};
    request.lixel_budget = 5303663739760811604;
    request.max_texture_size = kMaxImageSide;
    const auto plan = PlanShadowMaps(request);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    std::int64_t total = 0;
    for (const PlannedMap& m : plan->maps) {
        EXPECT_LE(m.map.width, request.max_texture_size) << m.name;
        EXPECT_LE(m.map.height, request.max_texture_size) << m.name;
        EXPECT_GE(m.lookup.guard, 0) << m.name;
        total += m.lixels;
    }
    EXPECT_LE(total, request.lixel_budget);
}

}  // namespace
}  // namespace lixel
