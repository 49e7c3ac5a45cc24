// Tests for scheduler.h: which maps a view needs, what is left out and why, the budget, and the
// lookup rule's coverage of every visible point (DESIGN §4.5; Chong & Gortler §3-4).
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/scheduler.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Uniform;

constexpr double kDegree = std::numbers::pi / 180.0;

SceneObject Box(const std::string& name, const Vec3& min, const Vec3& max) {
    SceneObject o;
    o.name = name;
    o.bounds = Aabb{min, max};
    return o;
}

// The paper's room: floor y = 0, wall z = -5, boxes standing on the floor, one of them near the
// viewer so its shadow falls outside the view, a light above and to the side.
PlanRequest FloorWallRequest() {
    PlanRequest r;
    r.viewer = Perspective(60.0 * kDegree, 1.0, 0.1, 100.0) *
               LookAt(Vec3(0, 3, 8), Vec3(0, 0.5, -2), Vec3::UnitY());
    r.viewport = {1024, 1024};
    r.light = Point(Vec3(4, 9, 3));
    r.objects = {Box("floor", Vec3(-10, -0.1, -5), Vec3(10, 0, 10)),
                 Box("wall", Vec3(-10, 0, -5.1), Vec3(10, 8, -5)),
                 Box("cube", Vec3(-1, 0, -2), Vec3(0, 1, -1)),
                 Box("ball", Vec3(1, 0.5, -3), Vec3(2, 1.5, -2)),
                 Box("pole", Vec3(-2.5, 0, 3), Vec3(-2.2, 4, 3.3))};
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}}, {"wall", Vec4(0, 0, 1, 5), {}}};
    r.lixel_budget = 512 * 512;
    return r;
}

std::vector<std::string> MapNames(const Plan& plan) {
    std::vector<std::string> names;
    for (const PlannedMap& m : plan.maps) names.push_back(m.name);
    return names;
}

const LeftOut* FindLeftOut(const Plan& plan, const std::string& item) {
    for (const LeftOut& l : plan.left_out) {
        if (l.item == item) return &l;
    }
    return nullptr;
}

// Every map's frustum holds a point it accepts: lixel in bounds, depth in [0, 1], q > 0.
void ExpectHeld(const PlannedMap& m, const Vec3& x) {
    const Vec4 p = m.map.matrix * Point(x);
    ASSERT_GT(p.w(), 0.0) << m.name;
    EXPECT_GE(p.z() / p.w(), -1e-6) << m.name << " point " << x.transpose();
    EXPECT_LE(p.z() / p.w(), 1.0 + 1e-6) << m.name << " point " << x.transpose();
}

TEST(Scheduler, FloorWallRoomYieldsFloorWallFallbackInThePapersOrder) {
    const auto plan = PlanShadowMaps(FloorWallRequest());
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_EQ(MapNames(*plan), (std::vector<std::string>{"plane floor", "plane wall", "fallback"}));
    const PlannedMap& floor = plan->maps[0];
    EXPECT_EQ(floor.role, MapRole::kPlane);
    EXPECT_EQ(floor.lookup.half_planes.size(), 1u);  // the floor/wall line
    EXPECT_EQ(plan->maps[1].lookup.half_planes.size(), 1u);
    EXPECT_EQ(plan->maps[2].role, MapRole::kFallback);
    EXPECT_LE(plan->total_lixels, 512 * 512);
    EXPECT_LT(plan->plane_scale, 1.0);  // two 1024-wide planes do not fit 512^2 at 1:1
    // The fallback keeps at least the paper's 128^2, less the rounding of its aspect ratio.
    const PlannedMap& fallback = plan->maps[2];
    EXPECT_GE(fallback.lixels, 128 * 128 - fallback.map.width - fallback.map.height);
    // The floor map is twisted so the floor/wall line is horizontal: wall points above it are
    // outside the floor map and go to the wall map.
    EXPECT_EQ(LookupMap(*plan, Point(Vec3(0.5, 2.0, -5.0))), 1);
    EXPECT_EQ(LookupMap(*plan, Point(Vec3(0.5, 0.0, -1.0))), 0);
    for (const PlannedMap& m : plan->maps) EXPECT_GT(m.expected_pixels, 0.0) << m.name;
    EXPECT_NE(FindLeftOut(*plan, "pass second_depth"), nullptr);
}

TEST(Scheduler, PlansFitTheBudgetAtOneLixelPerPixelWhenItAllows) {
    PlanRequest r = FloorWallRequest();
    r.viewport = {256, 256};
    r.lixel_budget = 1024 * 1024;
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_EQ(plan->plane_scale, 1.0);
    for (const PlannedMap& m : plan->maps) {
        if (m.role == MapRole::kPlane) {
            EXPECT_LE(m.diagnostics.residual_lixels, 1e-9);
        }
    }
    EXPECT_LE(plan->total_lixels, r.lixel_budget);
}

TEST(Scheduler, TableOverFloorYieldsTableFloorFallback) {
    PlanRequest r = FloorWallRequest();
    r.planes = {{"table", Vec4(0, 1, 0, -0.8),
                 {Vec3(-1.5, 0.8, 0.5), Vec3(1.5, 0.8, 0.5), Vec3(1.5, 0.8, -1.5),
                  Vec3(-1.5, 0.8, -1.5)}},
                {"floor", Vec4(0, 1, 0, 0), {}}};
    r.objects = {Box("floor", Vec3(-10, -0.1, -5), Vec3(10, 0, 10)),
                 Box("table", Vec3(-1.5, 0.7, -1.5), Vec3(1.5, 0.8, 0.5)),
                 Box("vase", Vec3(-0.2, 0.8, -0.7), Vec3(0.2, 1.4, -0.3)),
                 Box("pole", Vec3(-2.5, 0, 3), Vec3(-2.2, 4, 3.3))};
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_EQ(MapNames(*plan), (std::vector<std::string>{"plane table", "plane floor", "fallback"}));
    EXPECT_EQ(plan->maps[0].lookup.half_planes.size(), 4u);  // the table top's four edges
    EXPECT_EQ(LookupMap(*plan, Point(Vec3(0.0, 0.8, -0.5))), 0);  // on the table
    EXPECT_EQ(LookupMap(*plan, Point(Vec3(2.5, 0.0, -0.5))), 1);  // on the floor beside it
}

TEST(Scheduler, LeavesOutPlanesBehindTheCameraFacingAwayOrCoveredWithReasons) {
    PlanRequest r = FloorWallRequest();
    r.planes.push_back({"behind", Vec4(0, 0, -1, 12), {}});   // z = 12, behind the eye at z = 8
    r.planes.push_back({"ceiling", Vec4(0, -1, 0, 8), {}});   // faces down, light below it
    r.planes.push_back({"rug", Vec4(0, 1, 0, -0.001),         // on the floor, after it
                        {Vec3(-1, 0.001, 0), Vec3(1, 0.001, 0), Vec3(1, 0.001, -1),
                         Vec3(-1, 0.001, -1)}});
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    const LeftOut* behind = FindLeftOut(*plan, "plane behind");
    ASSERT_NE(behind, nullptr);
    EXPECT_NE(behind->reason.find("not in view"), std::string::npos) << behind->reason;
    const LeftOut* ceiling = FindLeftOut(*plan, "plane ceiling");
    ASSERT_NE(ceiling, nullptr);
    EXPECT_NE(ceiling->reason.find("faces away from the light"), std::string::npos);
    const LeftOut* rug = FindLeftOut(*plan, "plane rug");
    ASSERT_NE(rug, nullptr);
    EXPECT_NE(rug->reason.find("covered by an earlier plane"), std::string::npos) << rug->reason;
    EXPECT_EQ(MapNames(*plan), (std::vector<std::string>{"plane floor", "plane wall", "fallback"}));
}

TEST(Scheduler, FloorSeenFromAboveWithEveryShadowOnItNeedsNoFallback) {
    PlanRequest r;
    r.viewer = Perspective(50.0 * kDegree, 1.0, 0.5, 50.0) *
               LookAt(Vec3(0, 12, 0), Vec3(0, 0, 0), -Vec3::UnitZ());
    r.viewport = {512, 512};
    r.light = Point(Vec3(0.5, 20, 0.3));
    r.objects = {Box("floor", Vec3(-20, -0.1, -20), Vec3(20, 0, 20)),
                 Box("crate", Vec3(-1, 0, -1), Vec3(0, 1, 0)),
                 Box("stool", Vec3(1, 0, 1), Vec3(1.6, 0.6, 1.6))};
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}}};
    r.lixel_budget = 1024 * 1024;
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_EQ(MapNames(*plan), (std::vector<std::string>{"plane floor"}));
    const LeftOut* fallback = FindLeftOut(*plan, "fallback");
    ASSERT_NE(fallback, nullptr);
    EXPECT_NE(fallback->reason.find("not needed"), std::string::npos);
}

// A light in view among the objects, with open space above it: rays go every way but up.
TEST(Scheduler, LightInsideTheSceneKeepsOnlyTheCubeFacesItNeeds) {
    PlanRequest r = FloorWallRequest();
    r.objects.erase(r.objects.begin() + 1);  // no wall: nothing above the light
    r.scene_bounds = Aabb{Vec3(-10, -0.1, -5), Vec3(10, 8, 10)};
    r.light = Point(Vec3(0.0, 5.0, -2.0));
    r.planes.clear();
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    ASSERT_TRUE(plan->hull.light_inside);
    int faces = 0;
    for (const PlannedMap& m : plan->maps) {
        EXPECT_EQ(m.role, MapRole::kCubeFace);
        ++faces;
    }
    EXPECT_GE(faces, 1);
    EXPECT_LT(faces, 6);
    const LeftOut* up = FindLeftOut(*plan, "cube +y");  // nothing above the light
    ASSERT_NE(up, nullptr);
    EXPECT_EQ(up->reason, "holds no needed rays");
    EXPECT_LE(plan->total_lixels, r.lixel_budget);
}

TEST(Scheduler, PassesAreLeftOutUnlessAskedForAndCastersExist) {
    PlanRequest r = FloorWallRequest();
    r.passes.second_depth = true;
    r.passes.silhouette_map = true;
    r.objects[2].closed = false;  // the cube is an open shell
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_EQ(FindLeftOut(*plan, "pass second_depth"), nullptr);
    EXPECT_NE(FindLeftOut(*plan, "pass volumes"), nullptr);
    const auto& floor_passes = plan->maps[0].passes;
    EXPECT_NE(std::find(floor_passes.begin(), floor_passes.end(), Pass::kSecondDepth),
              floor_passes.end());
    ASSERT_FALSE(plan->warnings.empty());
    EXPECT_NE(plan->warnings[0].find("cube"), std::string::npos);

    r.objects = {Box("floor", Vec3(-10, -0.1, -5), Vec3(10, 0, 10))};  // nothing casts
    const auto bare = PlanShadowMaps(r);
    ASSERT_TRUE(bare.ok()) << bare.error().Message();
    const LeftOut* sd = FindLeftOut(*bare, "pass second_depth");
    ASSERT_NE(sd, nullptr);
    EXPECT_EQ(sd->reason, "no caster inside the needed rays");
}

// Random rooms, views, lights and budgets: the budget and the texture size always hold, and
// every point of a visible object is accepted by some map whose frustum and depth range hold it.
TEST(Scheduler, BudgetHoldsAndEveryVisiblePointIsCoveredOnRandomRooms) {
    std::mt19937_64 rng(12351);
    int planned = 0;
    for (int i = 0; i < 150; ++i) {
        PlanRequest r = FloorWallRequest();
        const Vec3 eye(Uniform(rng, -8, 8), Uniform(rng, 0.5, 7), Uniform(rng, -3, 9));
        const Vec3 target(Uniform(rng, -5, 5), Uniform(rng, 0, 3), Uniform(rng, -5, 2));
        r.viewer = Perspective(Uniform(rng, 30, 90) * kDegree, 1.0, 0.1, 100.0) *
                   LookAt(eye, target, Vec3::UnitY());
        r.viewport = {static_cast<int>(Uniform(rng, 64, 1024)),
                      static_cast<int>(Uniform(rng, 64, 1024))};
        // A light anywhere in the room but inside an object (a light inside a caster is dark).
        bool inside_object = true;
        while (inside_object) {
            r.light = i % 3 == 0 ? Vec4(Uniform(rng, -1, 1), Uniform(rng, 0.3, 1),
                                        Uniform(rng, -0.2, 1), 0)
                                 : Point(Vec3(Uniform(rng, -9, 9), Uniform(rng, 1, 7.9),
                                              Uniform(rng, -4, 9)));
            inside_object = false;
            for (const SceneObject& o : r.objects) {
                inside_object = inside_object ||
                                (r.light.w() != 0.0 &&
                                 (r.light.head<3>().array() > o.bounds.min.array() - 0.2).all() &&
                                 (r.light.head<3>().array() < o.bounds.max.array() + 0.2).all());
            }
        }
        r.lixel_budget = static_cast<std::int64_t>(Uniform(rng, 64 * 64, 2048 * 2048));
        r.max_texture_size = 2048;
        const auto plan = PlanShadowMaps(r);
        SCOPED_TRACE("configuration " + std::to_string(i) + " eye " +
                     std::to_string(eye.x()) + " " + std::to_string(eye.y()) + " " +
                     std::to_string(eye.z()) + " target " + std::to_string(target.x()) + " " +
                     std::to_string(target.y()) + " " + std::to_string(target.z()) + " light " +
                     std::to_string(r.light.x()) + " " + std::to_string(r.light.y()) + " " +
                     std::to_string(r.light.z()) + " " + std::to_string(r.light.w()));
        if (!plan.ok()) {
            // Only a view that misses the scene may be refused.
            EXPECT_EQ(plan.error().field, "viewer") << i << ": " << plan.error().Message();
            continue;
        }
        ++planned;
        EXPECT_LE(plan->total_lixels, r.lixel_budget) << i;
        for (const PlannedMap& m : plan->maps) {
            EXPECT_LE(m.map.width, 2048);
            EXPECT_LE(m.map.height, 2048);
            if (m.role != MapRole::kPlane) {  // no sliver maps (at most 16:1, with rounding)
                EXPECT_LE(std::max(m.map.width, m.map.height),
                          16 * std::min(m.map.width, m.map.height) + 16)
                    << m.name << " " << m.map.width << " x " << m.map.height;
            }
        }
        // Dense samples of the visible objects.
        const Mat4 pixel = PixelMatrix(r.viewer, r.viewport);
        int uncovered = 0;
        for (const SceneObject& o : r.objects) {
            for (int k = 0; k < 200; ++k) {
                const Vec3 x(Uniform(rng, o.bounds.min.x(), o.bounds.max.x()),
                             Uniform(rng, o.bounds.min.y(), o.bounds.max.y()),
                             Uniform(rng, o.bounds.min.z(), o.bounds.max.z()));
                const Vec4 v = pixel * Point(x);
                if (!(v.w() > 0.0)) continue;
                const double px = v.x() / v.w();
                const double py = v.y() / v.w();
                const double depth = (r.viewer * Point(x)).z() / v.w();
                if (px < 0 || py < 0 || px > r.viewport.width || py > r.viewport.height ||
                    depth < 0 || depth > 1) {
                    continue;  // not in view
                }
                if (x.y() < 0.0 || x.z() < -5.0) continue;  // under the floor, behind the wall
                const int index = LookupMap(*plan, Point(x));
                if (index < 0) {
                    ++uncovered;
                    continue;
                }
                ExpectHeld(plan->maps[index], x);
            }
        }
        EXPECT_EQ(uncovered, 0) << "configuration " << i;
    }
    EXPECT_GT(planned, 100);
}

// EstimatePixels' rule traced ray by ray with no culling and no tiles: the nearest needed plane
// surface (candidate planes: those the plan does not leave out before solving) or box entry,
// then the lookup rule. Same arithmetic, so the same counts bit for bit.
std::vector<double> ReferencePixels(const PlanRequest& r, const Plan& plan) {
    std::vector<size_t> candidates;
    for (size_t i = 0; i < r.planes.size(); ++i) {
        const LeftOut* out = FindLeftOut(plan, "plane " + r.planes[i].name);
        const bool before_solving =
            out != nullptr && (out->reason.starts_with("faces away") ||
                               out->reason.starts_with("seen from behind") ||
                               out->reason.starts_with("not in view") ||
                               out->reason.starts_with("needed set empty"));
        if (!before_solving) candidates.push_back(i);
    }
    const Aabb& bounds = r.scene_bounds;
    const double thickness = 1e-6 * bounds.Diagonal();
    const Mat4 inverse = r.viewer.inverse();
    const Mat4 pixel = PixelMatrix(r.viewer, r.viewport);
    std::vector<double> counts(plan.maps.size(), 0.0);
    const int n = 48;
    for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
            const double ndc_x = 2.0 * (sx + 0.5) / n - 1.0;
            const double ndc_y = 2.0 * (sy + 0.5) / n - 1.0;
            const Vec4 near = inverse * Vec4(ndc_x, ndc_y, 0.0, 1.0);
            const Vec4 far = inverse * Vec4(ndc_x, ndc_y, 1.0, 1.0);
            if (!(near.w() != 0.0)) continue;
            const Vec3 origin = near.head<3>() / near.w();
            const Vec3 direction = far.w() != 0.0 ? Vec3(far.head<3>() / far.w() - origin)
                                                  : Vec3(far.head<3>());
            double best = std::numeric_limits<double>::infinity();
            for (size_t i : candidates) {
                const Vec4 plane = r.planes[i].plane / r.planes[i].plane.head<3>().norm();
                const double denom = plane.head<3>().dot(direction);
                if (denom == 0.0) continue;
                const double t = -(plane.head<3>().dot(origin) + plane.w()) / denom;
                if (!(t > 0.0 && t < best)) continue;
                const Vec3 hit = origin + t * direction;
                const auto& poly = r.planes[i].polygon;
                bool inside = (hit.array() >= bounds.min.array() - thickness).all() &&
                              (hit.array() <= bounds.max.array() + thickness).all();
                for (size_t k = 0; inside && k < poly.size(); ++k) {
                    const Vec3 edge = poly[(k + 1) % poly.size()] - poly[k];
                    inside = plane.head<3>().dot(edge.cross(hit - poly[k])) >= 0.0;
                }
                if (inside) best = t;
            }
            for (const SceneObject& o : r.objects) {
                double t0 = 0.0, t1 = best;
                for (int a = 0; a < 3 && t0 <= t1; ++a) {
                    if (direction(a) == 0.0) {
                        if (origin(a) < o.bounds.min(a) || origin(a) > o.bounds.max(a)) t0 = 2 * t1;
                        continue;
                    }
                    double ta = (o.bounds.min(a) - origin(a)) / direction(a);
                    double tb = (o.bounds.max(a) - origin(a)) / direction(a);
                    if (ta > tb) std::swap(ta, tb);
                    t0 = std::max(t0, ta);
                    t1 = std::min(t1, tb);
                }
                if (t0 <= t1 && t0 > 0.0 && t0 < best) best = t0;
            }
            if (!std::isfinite(best)) continue;
            const Vec3 hit = origin + best * direction;
            if (!(pixel.row(3).dot(Point(hit)) > 0.0)) continue;
            const int index = LookupMap(plan, Point(hit));
            if (index >= 0) counts[index] += 1.0;
        }
    }
    for (double& count : counts) {
        count *= static_cast<double>(r.viewport.width) * r.viewport.height / (n * n);
    }
    return counts;
}

// The estimate skips rays by culls and by tiles whose corners prove them alike; on random rooms
// with tables and walls it must count exactly what tracing every ray counts.
TEST(Scheduler, ExpectedPixelsEqualTracingEveryRayOnRandomRooms) {
    std::mt19937_64 rng(20240611);
    int compared = 0;
    for (int i = 0; i < 120; ++i) {
        PlanRequest r = FloorWallRequest();
        r.scene_bounds = Aabb{Vec3(-10, -0.1, -5.1), Vec3(10, 8, 10)};
        r.planes.push_back({"side", Vec4(1, 0, 0, 10), {}});
        for (int k = 0; k < i % 7; ++k) {
            const double x = Uniform(rng, -8, 6), z = Uniform(rng, -4, 4);
            const double y = Uniform(rng, 0.3, 2), w = Uniform(rng, 0.3, 2), d = Uniform(rng, 0.3, 2);
            const std::string name = "table" + std::to_string(k);
            r.planes.push_back({name, Vec4(0, 1, 0, -y),
                                {Vec3(x, y, z + d), Vec3(x + w, y, z + d), Vec3(x + w, y, z),
                                 Vec3(x, y, z)}});
            r.objects.push_back(Box(name, Vec3(x, y - 0.05, z), Vec3(x + w, y, z + d)));
        }
        const Vec3 eye(Uniform(rng, -8, 8), Uniform(rng, 0.5, 7), Uniform(rng, -3, 9));
        const Vec3 target(Uniform(rng, -5, 5), Uniform(rng, 0, 3), Uniform(rng, -5, 2));
        r.viewport = {static_cast<int>(Uniform(rng, 64, 1024)),
                      static_cast<int>(Uniform(rng, 64, 1024))};
        r.viewer = Perspective(Uniform(rng, 30, 90) * kDegree,
                               static_cast<double>(r.viewport.width) / r.viewport.height, 0.1,
                               100.0) *
                   LookAt(eye, target, Vec3::UnitY());
        r.light = i % 3 == 0 ? Vec4(Uniform(rng, -1, 1), Uniform(rng, 0.3, 1),
                                    Uniform(rng, -0.2, 1), 0)
                             : Point(Vec3(Uniform(rng, -9, 9), Uniform(rng, 5, 7.9),
                                          Uniform(rng, -4, 9)));
        r.lixel_budget = static_cast<std::int64_t>(Uniform(rng, 256 * 256, 2048 * 2048));
        const auto plan = PlanShadowMaps(r);
        if (!plan.ok()) continue;
        ++compared;
        const std::vector<double> expected = ReferencePixels(r, *plan);
        for (size_t m = 0; m < plan->maps.size(); ++m) {
            EXPECT_EQ(plan->maps[m].expected_pixels, expected[m])
                << "configuration " << i << " map " << plan->maps[m].name;
        }
    }
    EXPECT_GT(compared, 100);
}

TEST(Scheduler, RefusesBadInputNamingTheField) {
    auto field = [](const PlanRequest& r) {
        const auto plan = PlanShadowMaps(r);
        return plan.ok() ? std::string("accepted") : plan.error().field;
    };
    PlanRequest r = FloorWallRequest();
    r.lixel_budget = 0;
    EXPECT_EQ(field(r), "lixel_budget");
    r = FloorWallRequest();
    r.planes[1].plane = Vec4(0, 0, 0, 1);
    EXPECT_EQ(field(r), "planes[1].plane");
    r = FloorWallRequest();
    r.planes[0].polygon = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0.5, 1)};
    EXPECT_EQ(field(r), "planes[0].polygon[2]");
    r = FloorWallRequest();
    r.objects[1].bounds.max.x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(field(r), "objects[1].bounds");
    r = FloorWallRequest();
    r.objects.clear();
    EXPECT_EQ(field(r), "objects");
    r = FloorWallRequest();
    r.light = Vec4::Zero();
    EXPECT_EQ(field(r), "light");
    r = FloorWallRequest();
    r.max_texture_size = 0;
    EXPECT_EQ(field(r), "max_texture_size");
    r = FloorWallRequest();
    r.viewer(3, 3) = std::numeric_limits<double>::infinity();
    EXPECT_EQ(field(r), "viewer[3][3]");
}

}  // namespace
}  // namespace lixel
