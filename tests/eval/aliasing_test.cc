// Tests for lixel::eval aliasing (aliasing.h, plan_metrics.h): m in closed form, the analytic
// Jacobian against finite differences, and m = 1 on the plane of a plane-optimal map.
#include <gtest/gtest.h>
#include <lixel/eval/aliasing.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/plan_metrics.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace lixel::eval {
using namespace lixel::scene;  // NOLINT: the scenes the metrics run on
namespace {

TEST(AliasingM, ClosedFormSingularValues) {
    EXPECT_NEAR(AliasingM(Mat2::Identity()), 1.0, 1e-15);
    const double a = 0.4;
    Mat2 rotation;
    rotation << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    EXPECT_NEAR(AliasingM(rotation), 1.0, 1e-15);
    // One pixel step moves half a lixel along y: a lixel spans two pixels there.
    EXPECT_NEAR(AliasingM(Mat2(Eigen::Vector2d(2.0, 0.5).asDiagonal())), 2.0, 1e-15);
    Mat2 shear;
    shear << 1, 1, 0, 1;  // singular values (sqrt(5) +- 1) / 2
    EXPECT_NEAR(AliasingM(shear), 2.0 / (std::sqrt(5.0) - 1.0), 1e-14);
    EXPECT_TRUE(std::isinf(AliasingM(Mat2::Zero())));
    Mat2 rank_one;
    rank_one << 1, 2, 2, 4;
    EXPECT_TRUE(std::isinf(AliasingM(rank_one)));
}

// lixel(p) for a pixel p, through the tangent plane (n, X0): intersect p's viewing ray with the
// plane and project into the light.
Vec2 LixelOfPixel(const Mat4& pixel, const Mat4& light, const Vec3& x0, const Vec3& n,
                  const Vec2& p) {
    const Mat4 inverse = pixel.inverse();
    const Vec4 a = inverse * Vec4(p.x(), p.y(), 0.0, 1.0);
    const Vec4 b = inverse * Vec4(p.x(), p.y(), 0.5, 1.0);
    const Vec3 o = a.head<3>() / a.w();
    const Vec3 d = b.head<3>() / b.w() - o;
    const Vec3 x = o + d * (n.dot(x0 - o) / n.dot(d));
    return ImageXy(light * Point(x));
}

TEST(PixelToLixelJacobian, MatchesCentralDifferences) {
    std::mt19937_64 rng(12351);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Viewport viewport{640, 480};
    int checked = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const Vec3 eye(4 * u(rng), 2 + 3 * u(rng), 6 + u(rng));
        const Mat4 pixel = PixelMatrix(
            Perspective(0.9, 640.0 / 480.0, 0.1, 100.0) * LookAt(eye, Vec3::Zero(), Vec3::UnitY()),
            viewport);
        const Vec3 lp(3 * u(rng), 6 + u(rng), 3 * u(rng));
        const Mat4 light =
            PixelMatrix(Perspective(1.2, 1.0, 0.5, 50.0) * LookAt(lp, Vec3::Zero(), Vec3::UnitY()),
                        {1024, 1024});
        const Vec3 x0(u(rng), 0.5 * u(rng), u(rng));
        const Vec3 n = Vec3(u(rng), 1.0, u(rng)).normalized();
        auto j = PixelToLixelJacobian(pixel, light, x0, n);
        if (!j) continue;
        const Vec2 p = ImageXy(pixel * Point(x0));
        const double h = 1e-3;
        Mat2 numeric;
        for (int k = 0; k < 2; ++k) {
            const Vec2 step = h * Vec2::Unit(k);
            numeric.col(k) = (LixelOfPixel(pixel, light, x0, n, p + step) -
                              LixelOfPixel(pixel, light, x0, n, p - step)) /
                             (2 * h);
        }
        EXPECT_LT((*j - numeric).norm(), 1e-5 * std::max(1.0, numeric.norm())) << trial;
        ++checked;
    }
    EXPECT_GT(checked, 150);
}

TEST(PixelToLixelJacobian, RefusesPointsNotImaged) {
    const Mat4 pixel = PixelMatrix(
        Perspective(0.9, 1.0, 0.1, 100.0) * LookAt(Vec3(0, 2, 5), Vec3::Zero(), Vec3::UnitY()),
        {64, 64});
    // Behind the viewer.
    auto r = PixelToLixelJacobian(pixel, pixel, Vec3(0, 2, 9), Vec3::UnitY());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "point");
    // A plane through the eye is seen edge-on.
    r = PixelToLixelJacobian(pixel, pixel, Vec3::Zero(), Vec3(0, 5, -2).normalized());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "normal");
}

// Floor/wall scene at 256 x 256 (fast), ground truth once for the tests below.
struct FloorWall {
    Scene scene = FloorWallScene();
    GroundTruth truth;

    FloorWall() {
        scene.camera.viewport = {256, 256};
        auto t = ComputeGroundTruth(scene);
        EXPECT_TRUE(t.ok());
        truth = std::move(t.value());
    }
};

const FloorWall& Fixture() {
    static const FloorWall f;
    return f;
}

// The plane map of plane `index`, solved directly with lixel::SolvePlaneMap.
PlaneMap SolveFor(const Scene& scene, int index, const CropOptions& crop) {
    PlaneMapRequest request;
    request.input.viewer = scene.camera.Viewer();
    request.input.viewport = scene.camera.viewport;
    request.input.light = scene.light;
    request.input.plane = scene.planes[index].plane;
    request.bounds = scene.Bounds();
    request.crop = crop;
    auto map = SolvePlaneMap(request);
    EXPECT_TRUE(map.ok()) << map.error().Message();
    return map.value();
}

void ExpectMOnPlane(int plane, const CropOptions& crop, double expected_m) {
    const FloorWall& f = Fixture();
    const PlaneMap map = SolveFor(f.scene, plane, crop);
    const std::vector<LightMap> maps = {map.crop.map};
    const AliasingResult r =
        Aliasing(f.truth, f.scene.camera.PixelMatrix(), maps, [](const Vec4&) { return 0; });
    int on_plane = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < f.truth.state.size(); ++i) {
        if (f.truth.plane[i] != plane) continue;
        ++on_plane;
        worst = std::max(worst, std::abs(r.m[i] - expected_m));
        ASSERT_NEAR(r.m[i], expected_m, 1e-6 * expected_m) << "pixel " << i;
    }
    EXPECT_GT(on_plane, 5000);
    ::testing::Test::RecordProperty("worst_m_error_plane_" + std::to_string(plane),
                                    std::to_string(worst));
}

TEST(Aliasing, PlaneOptimalMapIsExactlyOneOnItsPlane) {
    ExpectMOnPlane(0, CropOptions{}, 1.0);  // floor
    ExpectMOnPlane(1, CropOptions{}, 1.0);  // wall
}

TEST(Aliasing, TwistKeepsOneLixelPerPixel) {
    CropOptions crop;
    crop.twist = Twist::kMinimizeArea;
    ExpectMOnPlane(0, crop, 1.0);
}

TEST(Aliasing, UniformScaleSetsMToItsInverse) {
    CropOptions crop;
    crop.scale = 0.5;  // half a lixel per pixel each way: every lixel covers 2 x 2 pixels
    ExpectMOnPlane(0, crop, 2.0);
}

TEST(Aliasing, GroupsSplitPlanesFromElsewhere) {
    const FloorWall& f = Fixture();
    const PlaneMap map = SolveFor(f.scene, 0, CropOptions{});
    const std::vector<LightMap> maps = {map.crop.map};
    const AliasingResult r =
        Aliasing(f.truth, f.scene.camera.PixelMatrix(), maps, [](const Vec4&) { return 0; });
    std::int64_t on_planes = 0, visible = 0;
    for (std::size_t i = 0; i < f.truth.state.size(); ++i) {
        if (!f.truth.Visible(i)) continue;
        ++visible;
        if (f.truth.plane[i] >= 0) ++on_planes;
    }
    EXPECT_EQ(r.planes.pixels, on_planes);
    EXPECT_EQ(r.planes.pixels + r.elsewhere.pixels + r.unmapped, visible);
    // The floor map on the wall and the shapes: not one lixel per pixel any more.
    EXPECT_GT(r.planes.p95, 1.0 + 1e-3);
    EXPECT_GT(r.elsewhere.pixels, 1000);
}

TEST(Aliasing, PlanLookupGivesOneOnPlanesAtFullBudget) {
    const FloorWall& f = Fixture();
    auto plan = PlanShadowMaps(f.scene.MakePlanRequest(4 * 256 * 256));
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    ASSERT_EQ(plan->plane_scale, 1.0);
    const AliasingResult r = Aliasing(f.truth, f.scene.camera.PixelMatrix(), *plan);
    int checked = 0;
    for (std::size_t i = 0; i < f.truth.state.size(); ++i) {
        const int plane = f.truth.plane[i];
        if (plane < 0) continue;
        const int k = LookupMap(*plan, Point(f.truth.position[i]));
        ASSERT_GE(k, 0);
        const PlannedMap& m = plan->maps[k];
        if (m.role != MapRole::kPlane || m.plane_index != plane) continue;
        ASSERT_NEAR(r.m[i], 1.0, 1e-6) << "pixel " << i << " on plane " << plane;
        ++checked;
    }
    EXPECT_GT(checked, 20000);
    const LixelUse use = ComputeLixelUse(f.truth, *plan);
    EXPECT_EQ(use.allocated, plan->total_lixels);
    EXPECT_GT(use.Share(), 0.1);
    EXPECT_LE(use.Share(), 1.0);
}

// Aliasing's per-pixel m (its own closed form, without divisions in the derivatives) against
// AliasingM of the reference Jacobian, on every pixel: with the plan's maps, with the floor map
// on everything, and with a map that images only half the scene. The reference loses
// ~sqrt(eps) where the two singular values are close; result.m is a float: 1e-6 relative
// covers both.
TEST(Aliasing, PerPixelMatchesTheReferenceJacobian) {
    const FloorWall& f = Fixture();
    const Mat4 pixel = f.scene.camera.PixelMatrix();
    auto plan = PlanShadowMaps(f.scene.MakePlanRequest(4 * 256 * 256));
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    const std::vector<LightMap> floor_only = {SolveFor(f.scene, 0, CropOptions{}).crop.map};
    const std::vector<LightMap> plan_maps = PlanLightMaps(*plan);
    // A map whose w is world x: the half of the scene at x <= 0 is not imaged (m infinite).
    LightMap half;
    half.matrix << 0, 0, 1, 0,  //
        0, 1, 0, 0,             //
        0, 0, 0, 0,             //
        1, 0, 0, 0;
    half.width = half.height = 256;
    const std::vector<LightMap> half_only = {half};
    const MapSelector plan_select = PlanSelector(*plan);
    const MapSelector first = [](const Vec4&) { return 0; };
    for (const auto& [maps, select] :
         {std::pair{&plan_maps, &plan_select}, std::pair{&floor_only, &first},
          std::pair{&half_only, &first}}) {
        const AliasingResult r = Aliasing(f.truth, pixel, *maps, *select);
        int finite = 0, infinite = 0;
        for (std::size_t i = 0; i < f.truth.state.size(); ++i) {
            if (!f.truth.Visible(i)) {
                EXPECT_TRUE(std::isnan(r.m[i])) << "pixel " << i;
                continue;
            }
            const int k = (*select)(Point(f.truth.position[i]));
            if (k < 0) continue;
            auto j = PixelToLixelJacobian(pixel, (*maps)[k].matrix, f.truth.position[i],
                                          f.truth.normal[i].cast<double>());
            const double expected = j ? AliasingM(*j) : std::numeric_limits<double>::infinity();
            if (std::isinf(expected)) {
                ASSERT_TRUE(std::isinf(r.m[i])) << "pixel " << i;
                ++infinite;
                continue;
            }
            ASSERT_NEAR(r.m[i], expected, 1e-6 * expected) << "pixel " << i;
            ++finite;
        }
        EXPECT_GT(finite, 10000);
        if (maps == &half_only) {
            EXPECT_GT(infinite, 10000);
        }
    }
}

// The statistics do not depend on the order of the values (Aliasing gathers them in fixed
// chunks; the mean is a compensated sum, p95 a selection).
TEST(SummarizeAliasing, OrderDoesNotMatter) {
    std::mt19937_64 rng(12351);
    std::lognormal_distribution<double> m(0.5, 1.0);
    std::vector<double> values(200'000);
    for (double& v : values) v = m(rng);
    values[17] = std::numeric_limits<double>::infinity();
    const AliasingStats a = SummarizeAliasing(values);
    std::shuffle(values.begin(), values.end(), rng);
    const AliasingStats b = SummarizeAliasing(values);
    EXPECT_EQ(a.pixels, b.pixels);
    EXPECT_DOUBLE_EQ(a.mean, b.mean);
    EXPECT_EQ(a.p95, b.p95);
    EXPECT_EQ(a.over_threshold, b.over_threshold);
    std::sort(values.begin(), values.end());
    EXPECT_EQ(a.p95, values[static_cast<std::size_t>(std::ceil(0.95 * 200'000)) - 1]);
}

TEST(SummarizeAliasing, MeanPercentileShare) {
    const AliasingStats s = SummarizeAliasing({1.0, 1.0, 2.0, 4.0});
    EXPECT_EQ(s.pixels, 4);
    EXPECT_DOUBLE_EQ(s.mean, 2.0);
    EXPECT_DOUBLE_EQ(s.p95, 4.0);  // nearest rank: ceil(0.95 * 4) = 4th
    EXPECT_DOUBLE_EQ(s.over_threshold, 0.5);
    std::vector<double> many(100);
    for (int i = 0; i < 100; ++i) many[i] = i + 1;  // 1 .. 100
    EXPECT_DOUBLE_EQ(SummarizeAliasing(many).p95, 95.0);
    const AliasingStats inf = SummarizeAliasing({1.0, std::numeric_limits<double>::infinity()});
    EXPECT_DOUBLE_EQ(inf.mean, 1.0);  // finite values only
    EXPECT_TRUE(std::isinf(inf.p95));
    EXPECT_DOUBLE_EQ(inf.over_threshold, 0.5);
    EXPECT_EQ(SummarizeAliasing({}).pixels, 0);
}

}  // namespace
}  // namespace lixel::eval
