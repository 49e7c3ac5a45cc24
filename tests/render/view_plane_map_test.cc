// Tests for the view pass driven by a plan (scheduler.h): the shader picks maps exactly as
// LookupMap does, and plane-optimal maps beat a uniform map of the same lixel budget on the
// plane of interest (Chong & Gortler §4), most clearly on an elongated shadow under grazing light.
#include <lixel/render/image_io.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/scheduler.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// The scene's view, light, meshes and bounds as a plan request for `planes`.
PlanRequest RequestFor(const TestScene& s, std::vector<PlaneOfInterest> planes,
                       std::int64_t budget) {
    PlanRequest request;
    request.viewer = s.viewer;
    request.viewport = s.viewport;
    request.light = s.light;
    for (const Mesh& m : s.meshes) {
        request.objects.push_back(SceneObject{m.name, m.Bounds(), &m, m.closed});
    }
    request.scene_bounds = s.bounds;
    request.planes = std::move(planes);
    request.lixel_budget = budget;
    return request;
}

Plan PlanFloor(const TestScene& s, std::int64_t budget, PassRequest passes = {}) {
    PlanRequest request = RequestFor(s, {PlaneOfInterest{"floor", Vec4(0, 1, 0, 0), {}}}, budget);
    request.fallback_floor = budget / 8;
    request.passes = passes;
    auto plan = PlanShadowMaps(request);
    EXPECT_TRUE(plan.ok()) << plan.error().Message();
    return std::move(plan.value());
}

// A 0.3 x 1.6 x 0.3 pole on the floor slab lit from low on the side (about 14 degrees above
// the floor at the pole): its shadow runs several units across the floor.
TestScene GrazingPole(int size) {
    TestScene s = testing::SquareOverFloor(size);
    s.meshes[1] = testing::BoxMesh("pole", Vec3(-0.15, 0.0, -0.15), Vec3(0.15, 1.6, 0.15));
    s.shapes[1] = testing::Shape::Box(Vec3(-0.15, 0.0, -0.15), Vec3(0.15, 1.6, 0.15));
    s.viewer = testing::Viewer(Vec3(-1.0, 2.5, 3.0), Vec3(-1.8, 0.0, 0.0), 50.0, 1.0);
    s.light = Point(Vec3(6.0, 1.2, 1.0));
    return s;
}

TEST(ViewPlan, ShaderPicksTheMapLookupMapPicks) {
    const TestScene s = testing::SquareOverFloor(128);
    const Plan plan = PlanFloor(s, 128 * 128);
    ASSERT_GE(plan.maps.size(), 1u);
    const auto view = testing::RenderView(s, plan.maps, ShadowMethod::kDepth);
    const auto hits = testing::PrimaryHits(s.shapes, s.viewer, s.viewport);
    int compared = 0;
    int differ = 0;
    std::vector<int> used(plan.maps.size() + 1, 0);
    int floor = 0;  // pixels the floor's maps take (its footprint rectangles and unshadowed entry)
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits[i].shape < 0 || view.mask.pixels[i] < 0.0f) continue;
        ++compared;
        const int expected = LookupMap(plan, Point(hits[i].point));
        ++used[static_cast<std::size_t>(expected + 1)];
        floor += expected >= 0 && plan.maps[static_cast<std::size_t>(expected)].plane_index == 0;
        if (view.map_index[i] != expected) ++differ;
    }
    std::printf("[ measured ] plan of %zu maps: shader and LookupMap differ on %d of %d pixels\n",
                plan.maps.size(), differ, compared);
    EXPECT_GT(compared, 128 * 64);
    // The shader tests in float at the interpolated point; the CPU in double at the exact hit:
    // only pixels on a rule's boundary may go either way.
    EXPECT_LE(differ, compared / 500);
    EXPECT_GT(floor, compared / 2) << "the floor's plane maps hold most pixels";
}

// Cascaded shadow maps pick a map by the view depth limit of the lookup rule (world_limit):
// the shader's choice is LookupMap's, and the view's depth range spreads its pixels over
// several cascades, nearer ones first.
TEST(ViewPlan, ShaderPicksTheCascadeLookupMapPicks) {
    TestScene s = testing::SquareOverFloor(128);
    for (const Vec4& light : {s.light, Direction(Vec3(0.3, 1.0, 0.2))}) {
        s.light = light;
        const PlanRequest request = RequestFor(s, {}, 128 * 128);
        auto hull = ComputeExtentHull(request.viewer, request.light, request.scene_bounds);
        ASSERT_TRUE(hull.ok()) << hull.error().Message();
        auto plan = PlanBaseline(request, BaselineFitting::kCsm, *hull);
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        ASSERT_GE(plan->maps.size(), 2u);
        const auto view = testing::RenderView(s, plan->maps, ShadowMethod::kDepth);
        const auto hits = testing::PrimaryHits(s.shapes, s.viewer, s.viewport);
        int compared = 0;
        int differ = 0;
        std::vector<int> used(plan->maps.size() + 1, 0);
        for (std::size_t i = 0; i < hits.size(); ++i) {
            if (hits[i].shape < 0 || view.mask.pixels[i] < 0.0f) continue;
            ++compared;
            const int expected = LookupMap(*plan, Point(hits[i].point));
            ++used[static_cast<std::size_t>(expected + 1)];
            if (view.map_index[i] != expected) ++differ;
        }
        std::printf("[ measured ] %zu cascades: shader and LookupMap differ on %d of %d pixels\n",
                    plan->maps.size(), differ, compared);
        EXPECT_GT(compared, 128 * 64);
        EXPECT_LE(differ, compared / 500);
        EXPECT_EQ(used[0], 0) << "every visible pixel has a cascade";
        int cascades_used = 0;
        for (std::size_t k = 1; k < used.size(); ++k) cascades_used += used[k] > 0;
        EXPECT_GE(cascades_used, 2);
    }
}

TEST(ViewPlan, HalfPlanesAndFallbackFollowTheRule) {
    // Two maps by hand: the floor's plane map restricted to lixels x >= 0.6 W by a half-plane,
    // then a uniform fallback for everything else.
    const TestScene s = testing::SquareOverFloor(128);
    const LightMap floor = testing::FloorMap(s, 128 * 128);
    Plan plan;
    plan.maps = {
        testing::Planned(floor, {Pass::kDepth}, {Eigen::Vector3d(1.0, 0.0, -0.6 * floor.width)}),
        testing::Planned(testing::UniformMap(s, 96 * 96), {Pass::kDepth})};
    const auto view = testing::RenderView(s, plan.maps, ShadowMethod::kDepth);
    const auto hits = testing::PrimaryHits(s.shapes, s.viewer, s.viewport);
    int differ = 0;
    std::vector<int> used(3, 0);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits[i].shape < 0 || view.mask.pixels[i] < 0.0f) continue;
        const int expected = LookupMap(plan, Point(hits[i].point));
        ++used[static_cast<std::size_t>(expected + 1)];
        if (view.map_index[i] != expected) ++differ;
    }
    std::printf(
        "[ measured ] half-plane + fallback: %d pixels differ; plane map %d, fallback %d, "
        "none %d\n",
        differ, used[1], used[2], used[0]);
    EXPECT_GT(used[1], 1000);
    EXPECT_GT(used[2], 1000);
    EXPECT_LE(differ, (used[1] + used[2]) / 500);
}

struct Errors {
    testing::MaskComparison plane;
    testing::MaskComparison uniform;
    std::int64_t lixels = 0;
};

Errors CompareOnFloor(const TestScene& s, std::int64_t budget) {
    const Plan plan = PlanFloor(s, budget);
    Errors e;
    e.lixels = plan.total_lixels;
    const std::vector<PlannedMap> uniform = {
        testing::Planned(testing::UniformMap(s, plan.total_lixels), {Pass::kDepth})};
    const FloatImage truth = testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light);
    const auto hits = testing::PrimaryHits(s.shapes, s.viewer, s.viewport);
    const FloatImage floor_truth = testing::OnlyShape(truth, hits, 0);
    const auto planned = testing::RenderView(s, plan.maps, ShadowMethod::kDepth);
    const auto fitted = testing::RenderView(s, uniform, ShadowMethod::kDepth);
    if (const char* dir = std::getenv("LIXEL_TEST_IMAGES")) {
        const std::string base = std::string(dir) + "/plan_" + s.meshes[1].name;
        (void)WritePng(base + "_plane.png", MaskPreview(planned.mask));
        (void)WritePng(base + "_uniform.png", MaskPreview(fitted.mask));
        (void)WritePng(base + "_truth.png", MaskPreview(floor_truth));
    }
    e.plane = testing::CompareMasks(planned.mask, floor_truth, 1.5, 48);
    e.uniform = testing::CompareMasks(fitted.mask, floor_truth, 1.5, 48);
    return e;
}

void Print(const char* name, const Errors& e) {
    std::printf(
        "[ measured ] %s, %lld lixels: plane-optimal %d px wrong (max %.2f, mean %.2f px "
        "from the boundary), uniform %d px wrong (max %.2f, mean %.2f)\n",
        name, static_cast<long long>(e.lixels), e.plane.mismatched, e.plane.max_distance,
        e.plane.mean_distance, e.uniform.mismatched, e.uniform.max_distance,
        e.uniform.mean_distance);
}

// The boundary error is the share of floor pixels misclassified (DESIGN §7) and how far they
// lie from the visible true boundary; where the boundary runs behind the occluder in the view,
// a wrong pixel can be several pixels from the nearest visible one.
TEST(ViewPlan, PlaneMapsNoWorseThanUniformOnTheFloor) {
    const Errors e = CompareOnFloor(testing::SquareOverFloor(128), 128 * 128);
    Print("square over floor", e);
    EXPECT_LE(e.plane.mismatched, e.uniform.mismatched);
    EXPECT_LE(e.plane.max_distance, e.uniform.max_distance);
    EXPECT_LE(e.plane.max_distance, 1.5) << "one lixel per pixel on the floor";
}

TEST(ViewPlan, PlaneMapsStrictlyBetterOnTheElongatedShadow) {
    const Errors e = CompareOnFloor(GrazingPole(128), 128 * 128);
    Print("grazing pole", e);
    EXPECT_LT(e.plane.mismatched, e.uniform.mismatched);
    EXPECT_LE(e.plane.max_distance, e.uniform.max_distance);
    EXPECT_LE(e.plane.max_distance, 1.5);
}

}  // namespace
}  // namespace lixel::render

namespace lixel::render {
namespace {

// The floor map's edges are the viewport's (its needed rays are the floor in view): taps of
// pixels along the view's border read the map's guard band (scheduler.h kGuardLixels) and, for
// wider filters, the atlas's copies of the edge texels past it. Every filter must shade the open
// floor there as it shades the rest of it: lit where the truth is lit. Virtual samples at tap
// centres past the edge compared the floor's tangent plane there with the edge texel's depth,
// which belongs elsewhere on the floor: second depth left 128 of 3456 border pixels partly
// shadowed at r = 1 before they were clamped to the texels read. And past the floor's far edge,
// where the planned map's depth row ends, the tangent plane extrapolates below 0 and empty
// texels (0) shadowed it: 384 of the planned map's border pixels at r = 4, before empty texels
// were taken as holding no occluder.
TEST(ViewPlan, OpenFloorAtTheMapsEdgesShadesAsTheTruth) {
    TestScene s = testing::OpenSquareOverFloor(128);
    s.meshes.resize(1);  // the floor alone: lit everywhere, so any shadow is the filter's
    s.shapes.resize(1);
    s.viewer = testing::Viewer(Vec3(0.0, 2.5, 2.5), Vec3(0.0, 0.0, 0.0), 50.0, 1.0);
    // The floor's map alone (no guard band: taps past its edge read the atlas's copies), and as
    // the scheduler plans it (with its guard band).
    const std::vector<PlannedMap> bare = {
        testing::Planned(testing::FloorMap(s, 128 * 128), {Pass::kDepth, Pass::kSecondDepth})};
    std::vector<PlannedMap> planned = PlanFloor(s, 128 * 128).maps;
    ASSERT_EQ(planned.size(), 1u) << "the floor map alone holds every visible ray";
    EXPECT_EQ(planned[0].lookup.guard, kGuardLixels);
    planned[0].passes = {Pass::kDepth, Pass::kSecondDepth};
    const FloatImage truth = testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light);
    const std::vector<PlannedMap>* both[] = {&bare, &planned};
    for (const std::vector<PlannedMap>* maps : both) {
    for (ShadowMethod method : {ShadowMethod::kPcf, ShadowMethod::kSecondDepth}) {
        for (int radius : {1, 4}) {
            ShadowOptions options;
            options.pcf_radius = radius;
            const auto view = testing::RenderView(s, *maps, method, options);
            int border_lit = 0;
            int wrong = 0;
            for (int y = 0; y < s.viewport.height; ++y) {
                for (int x = 0; x < s.viewport.width; ++x) {
                    const int edge = std::min(std::min(x, y), std::min(s.viewport.width - 1 - x,
                                                                       s.viewport.height - 1 - y));
                    const std::size_t i = static_cast<std::size_t>(y) * s.viewport.width + x;
                    if (edge >= 8 || truth.at(x, y) != 1.0f || view.map_index[i] != 0) continue;
                    ++border_lit;
                    // Lit up to the float sum of (2r - 1)^2 tent weights (2e-7 at r = 4).
                    wrong += view.mask.at(x, y) < 1.0f - 1e-6f ? 1 : 0;
                }
            }
            const char* which = maps == &bare ? "bare" : "planned";
            std::printf("[ measured ] %s map, %s r = %d: %d of %d lit floor pixels within 8 px "
                        "of the map's edges not fully lit\n",
                        which, ShadowMethodName(method), radius, wrong, border_lit);
            EXPECT_GT(border_lit, 1000);
            EXPECT_EQ(wrong, 0) << which << " " << ShadowMethodName(method) << " r = " << radius;
        }
    }
    }
}

}  // namespace
}  // namespace lixel::render

namespace lixel::render {
namespace {

// Where a ray from the viewer's pixel centre meets the quad `corners` (convex, planar), or
// nothing: the distance along the ray.
std::optional<double> RayQuad(const Vec3& o, const Vec3& d, const std::vector<Vec3>& corners) {
    const Vec3 n = (corners[1] - corners[0]).cross(corners[2] - corners[1]);
    const double t = n.dot(corners[0] - o) / n.dot(d);
    if (!(t > 0.0)) return std::nullopt;
    const Vec3 p = o + t * d;
    for (size_t i = 0; i < corners.size(); ++i) {
        const Vec3& a = corners[i];
        const Vec3& b = corners[(i + 1) % corners.size()];
        if ((b - a).cross(p - a).dot(n) < 0.0) return std::nullopt;
    }
    return t;
}

// Two bounded planes of interest meeting at a convex ridge (a floor and a slope falling away from
// it), each with its own plane map; the lookup's half-planes (the polygons' edges) hand pixels
// from one map to the other on the ridge line. Nothing casts, so every filter must shade both
// planes lit right up to the seam: taps across it read the other plane, farther from the light,
// in the map's own texels or its guard band. Without the band and with virtual samples at
// unclamped tap centres, second depth at r = 4 left 256 of the 384 pixels by the ridge partly
// shadowed.
TEST(ViewPlan, PlanesShadeAsTheTruthOnTheSeamBetweenTheirMaps) {
    TestScene s = testing::OpenSquareOverFloor(128);
    const std::vector<Vec3> floor = {Vec3(-3, 0, 3), Vec3(3, 0, 3), Vec3(3, 0, 0), Vec3(-3, 0, 0)};
    const std::vector<Vec3> slope = {Vec3(-3, 0, 0), Vec3(3, 0, 0), Vec3(3, -0.9, -3),
                                     Vec3(-3, -0.9, -3)};
    s.meshes = {testing::QuadMesh("floor", floor), testing::QuadMesh("slope", slope)};
    s.shapes.clear();
    s.viewer = testing::Viewer(Vec3(0.0, 2.5, 4.0), Vec3(0.0, 0.0, -0.5), 50.0, 1.0);
    s.light = Point(Vec3(1.0, 6.0, 1.0));
    s.bounds = {Vec3(-3, -1, -3), Vec3(3, 1, 3)};
    const Vec3 slope_normal = (slope[1] - slope[0]).cross(slope[2] - slope[1]).normalized();
    const Vec4 slope_plane(slope_normal.x(), slope_normal.y(), slope_normal.z(), 0.0);
    auto plan = PlanShadowMaps(RequestFor(s,
                                          {PlaneOfInterest{"floor", Vec4(0, 1, 0, 0), floor},
                                           PlaneOfInterest{"slope", slope_plane, slope}},
                                          256 * 256));
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    int plane_maps = 0;
    for (PlannedMap& m : plan->maps) {
        plane_maps += m.role == MapRole::kPlane ? 1 : 0;
        m.passes = {Pass::kDepth, Pass::kSecondDepth};
    }
    ASSERT_EQ(plane_maps, 2);

    const Mat4 unproject = PixelMatrix(s.viewer, s.viewport).inverse();
    for (ShadowMethod method : {ShadowMethod::kPcf, ShadowMethod::kSecondDepth}) {
        for (int radius : {1, 4}) {
            ShadowOptions options;
            options.pcf_radius = radius;
            const auto view = testing::RenderView(s, plan->maps, method, options);
            int near_seam = 0;
            int wrong = 0;
            std::vector<int> used(plan->maps.size() + 1, 0);
            for (int y = 0; y < s.viewport.height; ++y) {
                for (int x = 0; x < s.viewport.width; ++x) {
                    const Vec4 a = unproject * Vec4(x + 0.5, y + 0.5, kClipDepthNear, 1.0);
                    const Vec4 b = unproject * Vec4(x + 0.5, y + 0.5, kClipDepthFar, 1.0);
                    const Vec3 o = a.head<3>() / a.w();
                    const Vec3 d = b.head<3>() / b.w() - o;
                    auto t = RayQuad(o, d, floor);
                    if (!t) t = RayQuad(o, d, slope);
                    if (!t || std::abs((o + *t * d).z()) > 0.15) continue;  // 0.15 of the ridge
                    const std::size_t i = static_cast<std::size_t>(y) * s.viewport.width + x;
                    if (view.mask.pixels[i] < 0.0f) continue;
                    ++near_seam;
                    ++used[static_cast<std::size_t>(view.map_index[i] + 1)];
                    // Lit up to the float sum of the filter's tent weights.
                    wrong += view.mask.pixels[i] < 1.0f - 1e-6f ? 1 : 0;
                }
            }
            std::printf("[ measured ] seam, %s r = %d: %d of %d pixels within 0.15 of the ridge "
                        "not fully lit (maps used: %d, %d)\n",
                        ShadowMethodName(method), radius, wrong, near_seam, used[1], used[2]);
            EXPECT_GT(used[1], 50) << "the seam is between the two plane maps";
            EXPECT_GT(used[2], 50);
            EXPECT_EQ(wrong, 0) << ShadowMethodName(method) << " r = " << radius;
        }
    }
}

}  // namespace
}  // namespace lixel::render
