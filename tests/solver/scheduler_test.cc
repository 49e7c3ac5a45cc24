// Tests for scheduler.h: which maps a view needs, what is left out and why, the budget, and the
// lookup rule's coverage of every visible point (DESIGN §4.5; Chong & Gortler §3-4).
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/crop.h>
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

using testing::Box;
using testing::Uniform;

constexpr double kDegree = std::numbers::pi / 180.0;

// The paper's room: floor y = 0, wall z = -5, boxes standing on the floor, one of them near the
// viewer so its shadow falls outside the view, a light above and to the side.
PlanRequest FloorWallRequest() {
    PlanRequest r;
    r.viewer = Perspective(60.0 * kDegree, 1.0, 0.1, 100.0) *
               LookAt(Vec3(0, 3, 8), Vec3(0, 0.5, -2), Vec3::UnitY());
    r.viewport = {1024, 1024};
    r.light = Point(Vec3(4, 9, 3));
    r.objects = testing::FloorWallRoomObjects();
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

// The paper's layout (§3-4): each plane map over its whole needed polygon (footprints off).
PlanRequest WholePlaneMaps(PlanRequest r) {
    r.footprints.enabled = false;
    return r;
}

TEST(Scheduler, FloorWallRoomYieldsFloorWallFallbackInThePapersOrder) {
    const auto plan = PlanShadowMaps(WholePlaneMaps(FloorWallRequest()));
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
    const auto plan = PlanShadowMaps(WholePlaneMaps(r));
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
    const auto plan = PlanShadowMaps(WholePlaneMaps(r));
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
    // The floor's footprint rectangles and its unshadowed entry, nothing else.
    ASSERT_FALSE(plan->maps.empty());
    for (const PlannedMap& m : plan->maps) {
        EXPECT_EQ(m.role, MapRole::kPlane) << m.name;
        EXPECT_EQ(m.plane_index, 0) << m.name;
    }
    EXPECT_TRUE(plan->maps.back().lookup.unshadowed);
    const LeftOut* fallback = FindLeftOut(*plan, "fallback");
    ASSERT_NE(fallback, nullptr);
    EXPECT_NE(fallback->reason.find("not needed"), std::string::npos);
}

// An orthographic viewer straight above the floor (its centre of projection at infinity, up):
// the floor faces it, so the floor gets its plane map, one lixel per pixel, and every floor
// point in view is looked up there.
TEST(Scheduler, OrthographicViewerAboveTheFloorGetsTheFloorMap) {
    PlanRequest r;
    r.viewer =
        Orthographic(6.0, 6.0, 0.5, 50.0) * LookAt(Vec3(0, 12, 0), Vec3(0, 0, 0), -Vec3::UnitZ());
    r.viewport = {512, 512};
    r.light = Point(Vec3(0.5, 20, 0.3));
    r.objects = {Box("floor", Vec3(-20, -0.1, -20), Vec3(20, 0, 20)),
                 Box("crate", Vec3(-1, 0, -1), Vec3(0, 1, 0)),
                 Box("stool", Vec3(1, 0, 1), Vec3(1.6, 0.6, 1.6))};
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}}};
    r.lixel_budget = 1024 * 1024;
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    const LeftOut* floor_out = FindLeftOut(*plan, "plane floor");
    EXPECT_EQ(floor_out, nullptr) << floor_out->reason;
    ASSERT_FALSE(plan->maps.empty());
    const PlannedMap& floor = plan->maps[0];
    ASSERT_EQ(floor.plane_index, 0);
    EXPECT_EQ(floor.scale, 1.0);
    // The plane's points keep their pixel to the rounding of lixel coordinates up to the map's
    // side S, as for perspective viewers (plane_optimal_stiff_test): 8 eps S.
    EXPECT_LE(floor.diagnostics.residual_lixels,
              8 * std::numeric_limits<double>::epsilon() *
                  std::max(floor.map.width, floor.map.height));
    std::mt19937_64 rng(7);
    for (int k = 0; k < 500; ++k) {
        const Vec3 x(Uniform(rng, -5.9, 5.9), 0.0, Uniform(rng, -5.9, 5.9));
        const int index = LookupMap(*plan, Point(x));
        ASSERT_GE(index, 0) << x.transpose();
        EXPECT_EQ(plan->maps[index].plane_index, 0) << x.transpose();
    }
}

// Planes that are left out, or that the viewer sees from behind, hide nothing the viewer sees
// in front of them: a partition wall behind the viewer facing the next room, a ceiling seen
// from below and a screen turned away from the light leave the floor and the wall exactly as
// they are without them.
TEST(Scheduler, PlanesLeftOutOrSeenFromBehindDoNotCutTheOthers) {
    const auto reference = PlanShadowMaps(FloorWallRequest());
    ASSERT_TRUE(reference.ok()) << reference.error().Message();
    const std::vector<PlaneOfInterest> extras = {
        {"next_room_wall", Vec4(0, 0, 1, -10), {}},  // z = 10, behind the eye at z = 8
        {"ceiling", Vec4(0, 1, 0, -8), {}},          // y = 8 facing up, the eye below it
        {"screen", Vec4(-1, 0, 0, 3), {}},           // x = 3 facing the eye, its back lit
    };
    for (const PlaneOfInterest& extra : extras) {
        PlanRequest r = FloorWallRequest();
        r.planes.push_back(extra);
        const auto plan = PlanShadowMaps(r);
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        const LeftOut* out = FindLeftOut(*plan, "plane " + extra.name);
        ASSERT_NE(out, nullptr) << extra.name;
        for (const char* kept : {"plane floor", "plane wall"}) {
            const LeftOut* lost = FindLeftOut(*plan, kept);
            EXPECT_EQ(lost, nullptr) << extra.name << ": " << kept << " " << lost->reason;
        }
        EXPECT_EQ(MapNames(*plan), MapNames(*reference)) << extra.name;
        // The plane maps; the fallback may shrink where a screen facing the viewer hides part
        // of the view.
        for (size_t m = 0; m < 2 && m < std::min(plan->maps.size(), reference->maps.size()); ++m) {
            EXPECT_EQ(plan->maps[m].map.matrix, reference->maps[m].map.matrix)
                << extra.name << " " << plan->maps[m].name;
            EXPECT_EQ(plan->maps[m].lookup.half_planes.size(),
                      reference->maps[m].lookup.half_planes.size())
                << extra.name << " " << plan->maps[m].name;
        }
    }
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

// PlanRequest::cancelled is polled in every step that visits objects, receivers or rays, and the
// first true ends the plan then and there, with the request's error; never answering true leaves
// the plan as it is without a poll. 400 seeded boxes on the floor (so every step has objects to
// visit), second depth asked for (the passes' caster test), stopped at 10 points spread over
// all of the plan's polls.
TEST(Scheduler, ACancelledRequestEndsItsPlanAtTheFirstTruePollInEveryStep) {
    PlanRequest r = FloorWallRequest();
    r.passes.second_depth = true;
    std::mt19937_64 rng(27);
    std::uniform_real_distribution<double> x(-9.5, 9.5), z(-4.5, 9.5), side(0.05, 1.0);
    while (r.objects.size() < 400) {
        const Vec3 c(x(rng), 0.0, z(rng));
        const Vec3 half(side(rng) / 2, side(rng), side(rng) / 2);
        r.objects.push_back(Box("box", c - Vec3(half.x(), 0, half.z()), c + half));
    }
    const auto unpolled = PlanShadowMaps(r);
    ASSERT_TRUE(unpolled.ok()) << unpolled.error().Message();

    long calls = 0;
    long stop_at = -1;  // never
    r.cancelled = [&] { return ++calls == stop_at; };
    const auto polled = PlanShadowMaps(r);
    ASSERT_TRUE(polled.ok()) << polled.error().Message();
    const long total = calls;
    ASSERT_GT(total, 20);  // 400 objects, thousands of receivers: polled every 64 of them
    ASSERT_EQ(polled->maps.size(), unpolled->maps.size());
    for (size_t i = 0; i < polled->maps.size(); ++i) {
        EXPECT_EQ(polled->maps[i].map.matrix, unpolled->maps[i].map.matrix) << i;
        EXPECT_EQ(polled->maps[i].expected_pixels, unpolled->maps[i].expected_pixels) << i;
    }
    EXPECT_EQ(polled->total_lixels, unpolled->total_lixels);

    for (int k = 0; k < 10; ++k) {
        calls = 0;
        stop_at = 1 + (total - 1) * k / 9;
        const auto stopped = PlanShadowMaps(r);
        ASSERT_FALSE(stopped.ok()) << "stop at poll " << stop_at << " of " << total;
        EXPECT_EQ(stopped.error().field, "request");
        EXPECT_EQ(stopped.error().reason, kPlanCancelled);
        EXPECT_EQ(calls, stop_at) << "polled on past the first true";
    }
}

// Random rooms, views (one in four orthographic), lights and budgets, some with a partition
// behind the viewer facing the next room: the budget and the texture size always hold, every
// point of a visible object is accepted by some map whose frustum and depth range hold it, and
// every point of a plane map's needed polygon is looked up in that map for a perspective viewer
// (the floor comes first, and a wall point's light ray meets the floor only beyond the floor/wall
// line or behind the light, where the floor map's lookup refuses it) and in a plane map for any.
TEST(Scheduler, BudgetHoldsAndEveryVisiblePointIsCoveredOnRandomRooms) {
    std::mt19937_64 rng(12351);
    int planned = 0;
    int orthographic = 0;
    int plane_points = 0;
    int taken = 0;  // plane points an earlier plane map takes
    int unshadowed = 0;  // plane points lit by construction
    for (int i = 0; i < 150; ++i) {
        PlanRequest r = FloorWallRequest();
        const Vec3 eye(Uniform(rng, -8, 8), Uniform(rng, 0.5, 7), Uniform(rng, -3, 9));
        const Vec3 target(Uniform(rng, -5, 5), Uniform(rng, 0, 3), Uniform(rng, -5, 2));
        const double fovy = Uniform(rng, 30, 90) * kDegree;
        if (i % 4 == 1) {
            // The same field at the target's distance, seen from infinitely far behind the eye.
            const double half = std::tan(0.5 * fovy) * (target - eye).norm();
            r.viewer = Orthographic(half, half, 0.1, 100.0) * LookAt(eye, target, Vec3::UnitY());
        } else {
            r.viewer = Perspective(fovy, 1.0, 0.1, 100.0) * LookAt(eye, target, Vec3::UnitY());
        }
        if (i % 5 == 2) {
            r.planes.push_back({"partition", Vec4(0, 0, 1, -(eye.z() + Uniform(rng, 0.2, 3))), {}});
        }
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
        SCOPED_TRACE("configuration " + std::to_string(i) + " eye " + std::to_string(eye.x()) +
                     " " + std::to_string(eye.y()) + " " + std::to_string(eye.z()) + " target " +
                     std::to_string(target.x()) + " " + std::to_string(target.y()) + " " +
                     std::to_string(target.z()) + " light " + std::to_string(r.light.x()) + " " +
                     std::to_string(r.light.y()) + " " + std::to_string(r.light.z()) + " " +
                     std::to_string(r.light.w()) + (i % 4 == 1 ? " orthographic" : ""));
        if (!plan.ok()) {
            // Only a view that misses the scene may be refused.
            EXPECT_EQ(plan.error().field, "viewer") << i << ": " << plan.error().Message();
            continue;
        }
        ++planned;
        orthographic += i % 4 == 1 ? 1 : 0;
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
        // A partition behind a perspective viewer, facing away, hides nothing in view (one across
        // an orthographic viewer's near face may hide some or all of the room); and a plane is
        // seen from behind only when the eye (or, orthographic, the direction back toward the
        // viewer) is on its back side.
        for (size_t p = 0; p < 2; ++p) {
            const std::string name = "plane " + r.planes[p].name;
            const LeftOut* out = FindLeftOut(*plan, name);
            if (out == nullptr) continue;
            if (i % 4 != 1) {
                EXPECT_EQ(out->reason.find("partition"), std::string::npos)
                    << name << ": " << out->reason;
            }
            if (out->reason.starts_with("seen from behind")) {
                const Vec4 eye_point = i % 4 == 1 ? Direction(eye - target) : Point(eye);
                EXPECT_LE(r.planes[p].plane.dot(eye_point), 0.0) << name << ": " << out->reason;
            }
        }
        // Lit by construction: nothing but the floor and the wall, which no light ray to a point
        // in front of them crosses, lies between the point and the light (the boxes as they
        // are, unthickened: an independent slab test).
        const auto ExpectLit = [&](const Vec3& x, const std::string& map) {
            const Vec3 toward = r.light.w() == 0.0 ? Vec3(r.light.head<3>())
                                                  : Vec3(r.light.head<3>() - x);
            const double reach = r.light.w() == 0.0 ? 1e9 : 1.0;
            for (const SceneObject& caster : r.objects) {
                if (caster.name == "floor" || caster.name == "wall") continue;
                EXPECT_FALSE(std::isfinite(testing::BoxEntry(x, toward, caster.bounds, reach)))
                    << x.transpose() << " in " << map << " is shadowed by " << caster.name;
            }
        };
        // Points inside each plane map's needed polygon, away from its edges by rounding only.
        for (size_t m = 0; m < plan->maps.size(); ++m) {
            const PlannedMap& map = plan->maps[m];
            // (A footprint rectangle may hold only shadows out of view: no needed polygon.)
            if (map.role != MapRole::kPlane || map.needed_polygon.empty()) continue;
            for (int k = 0; k < 100; ++k) {
                Vec3 x = Vec3::Zero();
                double total = 0.0;
                for (const Vec3& v : map.needed_polygon) {
                    const double weight = Uniform(rng, 0.01, 1.0);
                    x += weight * v;
                    total += weight;
                }
                x /= total;
                ++plane_points;
                const int index = LookupMap(*plan, Point(x));
                if (index >= 0 && plan->maps[index].lookup.unshadowed) {
                    ExpectLit(x, plan->maps[index].name);
                    ++unshadowed;
                }
                if (index == static_cast<int>(m)) continue;
                // The plane's own footprint rectangles come first: its unshadowed entry takes
                // what they leave, and overlapping rectangles share.
                if (index >= 0 && index < static_cast<int>(m) &&
                    plan->maps[index].plane_index == map.plane_index &&
                    plan->maps[index].footprint) {
                    continue;
                }
                ++taken;
                // Earlier planes win shared rays (DESIGN §4.5). A perspective viewer's near face
                // lies inside the room, so the floor and the wall hide their back sides and each
                // map's lookup stops at the floor/wall line: no map takes the other's points. An
                // orthographic viewer's near face may poke through the wall's plane and see the
                // floor behind it; the floor map then holds rays through the wall too, and may
                // take its points (a correct shadow, at the floor map's sampling).
                ASSERT_EQ(i % 4, 1) << map.name << " point " << x.transpose() << " in "
                                    << (index < 0 ? "no map" : plan->maps[index].name);
                ASSERT_GE(index, 0) << map.name << " point " << x.transpose() << " in no map";
                ASSERT_LT(index, static_cast<int>(m))
                    << map.name << " point " << x.transpose() << " in " << plan->maps[index].name;
                ASSERT_EQ(plan->maps[index].role, MapRole::kPlane);
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
                if (plan->maps[index].lookup.unshadowed) {
                    // An object point inside its own box is in that box's shadow volume.
                    ExpectLit(x, plan->maps[index].name);
                    continue;
                }
                ExpectHeld(plan->maps[index], x);
            }
        }
        EXPECT_EQ(uncovered, 0) << "configuration " << i;
    }
    EXPECT_GT(planned, 100);
    EXPECT_GT(orthographic, 25);
    EXPECT_GT(plane_points, 10000);
    EXPECT_LT(taken, plane_points / 20);
    EXPECT_GT(unshadowed, 1000);
    RecordProperty("plane_points_taken_by_earlier_maps", std::to_string(taken));
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
                const double t0 = testing::BoxEntry(origin, direction, o.bounds, best);
                if (t0 > 0.0 && t0 < best) best = t0;
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

// Each map's expected pixels in `plan` are those ReferencePixels counts.
void ExpectPixelsOfTracingEveryRay(const PlanRequest& r, const Plan& plan, int configuration) {
    const std::vector<double> expected = ReferencePixels(r, plan);
    for (size_t m = 0; m < plan.maps.size(); ++m) {
        EXPECT_EQ(plan.maps[m].expected_pixels, expected[m])
            << "configuration " << configuration << " map " << plan.maps[m].name;
    }
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
        // Boxes anywhere in the room: in view, beside it and behind the eye (which every ray
        // and tile skips by its screen rectangle).
        for (int k = 0; k < i % 11; ++k) {
            const Vec3 lo(Uniform(rng, -10, 9), Uniform(rng, 0, 7), Uniform(rng, -5, 9));
            const Vec3 size(Uniform(rng, 0.05, 1), Uniform(rng, 0.05, 1), Uniform(rng, 0.05, 1));
            r.objects.push_back(Box("box" + std::to_string(k), lo, lo + size));
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
        ExpectPixelsOfTracingEveryRay(r, *plan, i);
    }
    EXPECT_GT(compared, 100);
}

// Seeded crowded room `i`: 4 000 + 400 i boxes at every depth, some stacked on others sharing a
// face, seen from the room's front across it, so that thousands of boxes are on screen.
PlanRequest CrowdedRoom(std::mt19937_64& rng, int i) {
    PlanRequest r = FloorWallRequest();
    r.scene_bounds = Aabb{Vec3(-10, -0.1, -5.1), Vec3(10, 8, 10)};
    const int boxes = 4000 + 400 * i;
    for (int k = 0; static_cast<int>(r.objects.size()) < boxes; ++k) {
        const Vec3 lo(Uniform(rng, -10, 9.5), k % 4 == 0 ? 0.0 : Uniform(rng, 0, 7),
                      Uniform(rng, -5, 9.5));
        const double side = k % 9 == 0 ? Uniform(rng, 1, 3) : Uniform(rng, 0.02, 0.6);
        const Vec3 size(side, Uniform(rng, 0.02, 1) * side, Uniform(rng, 0.5, 1) * side);
        r.objects.push_back(Box("box" + std::to_string(k), lo, lo + size));
        if (k % 13 == 0) {  // a box on top of it, sharing its face
            const Vec3 up(lo.x(), lo.y() + size.y(), lo.z());
            r.objects.push_back(Box("stacked" + std::to_string(k), up, up + size));
        }
    }
    const Vec3 eye(Uniform(rng, -6, 6), i % 3 == 1 ? 7.5 : Uniform(rng, 0.3, 4),
                   Uniform(rng, 8, 9.8));
    const Vec3 target(Uniform(rng, -3, 3), i % 3 == 2 ? 4.5 : Uniform(rng, 0, 2),
                      Uniform(rng, -5, -2));
    const int width = static_cast<int>(Uniform(rng, 256, 1024));
    r.viewport = {width, static_cast<int>(width * Uniform(rng, 0.5, 1.2))};
    r.viewer = Perspective(Uniform(rng, 60, 90) * kDegree,
                           static_cast<double>(r.viewport.width) / r.viewport.height, 0.1, 100.0) *
               LookAt(eye, target, Vec3::UnitY());
    r.light = i % 2 == 0
                  ? Vec4(Uniform(rng, -1, 1), Uniform(rng, 0.3, 1), Uniform(rng, -0.2, 1), 0)
                  : Point(Vec3(Uniform(rng, -9, 9), Uniform(rng, 5, 7.9), Uniform(rng, -4, 9)));
    r.lixel_budget = 1024 * 1024;
    return r;
}

// Boxes a ray of `r` meets on average, by their screen rectangles (boxes wholly in front of the
// eye).
double BoxesPerRay(const PlanRequest& r) {
    double covered = 0.0;
    for (const SceneObject& o : r.objects) {
        double x0 = 1.0, x1 = -1.0, y0 = 1.0, y1 = -1.0;
        bool in_front = true;
        for (int k = 0; k < 8 && in_front; ++k) {
            const Vec4 clip = r.viewer * Point(BoxCorner(o.bounds, k));
            in_front = clip.w() > 0.0;
            x0 = std::min(x0, clip.x() / clip.w());
            x1 = std::max(x1, clip.x() / clip.w());
            y0 = std::min(y0, clip.y() / clip.w());
            y1 = std::max(y1, clip.y() / clip.w());
        }
        const double w = std::min(x1, 1.0) - std::max(x0, -1.0);
        const double h = std::min(y1, 1.0) - std::max(y0, -1.0);
        if (in_front && w > 0.0 && h > 0.0) covered += w * h;
    }
    return covered / 4.0;  // the screen is 2 x 2 in NDC
}

// A crowd of boxes (rays meet more than kBoxesPerRayByDepth in scheduler_pixels.cc: the cells list
// them nearest first and a traced ray stops each list at its first box beyond its hit): the counts
// must still be those of tracing every ray against every box, with boxes in view at every depth,
// stacked, touching, beside the view and behind the eye, under viewers looking across, down onto
// and up into the room.
TEST(Scheduler, ExpectedPixelsEqualTracingEveryRayInACrowd) {
    std::mt19937_64 rng(20261206);
    int compared = 0;
    for (int i = 0; i < 6; ++i) {
        const PlanRequest r = CrowdedRoom(rng, i);
        EXPECT_GE(BoxesPerRay(r), 4.0) << "configuration " << i;
        const auto plan = PlanShadowMaps(r);
        ASSERT_TRUE(plan.ok()) << "configuration " << i << ": " << plan.error().Message();
        ++compared;
        ExpectPixelsOfTracingEveryRay(r, *plan, i);
    }
    EXPECT_EQ(compared, 6);
}

// A request with one bounded plane of interest: `polygon` on the plane with unit normal `n`
// through `origin`, vertices given in the plane's (u, v) coordinates with u x v = n, in the
// paper's room.
PlanRequest TableRequest(const Vec3& origin, const Vec3& n, const std::vector<Vec2>& uv) {
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 u = helper.cross(n).normalized();
    const Vec3 v = n.cross(u);
    PlaneOfInterest table{"table", Vec4(n.x(), n.y(), n.z(), -n.dot(origin)), {}};
    for (const Vec2& p : uv) table.polygon.push_back(origin + p.x() * u + p.y() * v);
    PlanRequest r = FloorWallRequest();
    r.planes.insert(r.planes.begin(), table);
    return r;
}

std::string RefusedField(const PlanRequest& r) {
    const auto plan = PlanShadowMaps(r);
    return plan.ok() ? std::string("accepted") : plan.error().field;
}

// EstimatePixels and the lookup's edge tests read a bounded polygon as convex and
// counter-clockwise about its plane's normal (scheduler.h). Random convex polygons on random
// planes are accepted as given; reversed, they are refused at vertex 0, where they first turn
// clockwise; with one vertex pushed inside the chord of its neighbours, they are refused at
// exactly that vertex; a pentagram (every turn counter-clockwise, wound twice) is refused.
TEST(Scheduler, RefusesBoundedPolygonsThatAreNotConvexAndCounterClockwise) {
    std::mt19937_64 rng(9);
    int reflex_named = 0;
    for (int i = 0; i < 200; ++i) {
        const Vec3 n = i % 2 == 0 ? Vec3::UnitY() : testing::RandomUnit(rng);
        const Vec3 origin(Uniform(rng, -2, 2), Uniform(rng, 0.5, 2), Uniform(rng, -3, 1));
        const int count = 3 + i % 6;
        // Sorted angles on an ellipse: convex, counter-clockwise in (u, v).
        std::vector<double> angles(count);
        for (double& a : angles) a = Uniform(rng, 0.0, 2.0 * std::numbers::pi);
        std::sort(angles.begin(), angles.end());
        const double a = Uniform(rng, 0.3, 2), b = Uniform(rng, 0.3, 2);
        std::vector<Vec2> uv;
        for (double t : angles) uv.emplace_back(a * std::cos(t), b * std::sin(t));
        SCOPED_TRACE("polygon " + std::to_string(i) + " of " + std::to_string(count));
        const std::string given = RefusedField(TableRequest(origin, n, uv));
        EXPECT_EQ(given.find("planes[0].polygon"), std::string::npos) << given;

        std::vector<Vec2> reversed(uv.rbegin(), uv.rend());
        EXPECT_EQ(RefusedField(TableRequest(origin, n, reversed)), "planes[0].polygon[0]");

        if (count < 4) continue;
        // Vertex k moved to 30% of the way from its neighbours' midpoint to the centroid: a
        // reflex vertex, and every other turn still counter-clockwise.
        const int k = static_cast<int>(Uniform(rng, 0, count - 1e-9));
        const Vec2 mid = 0.5 * (uv[(k + count - 1) % count] + uv[(k + 1) % count]);
        Vec2 centroid = Vec2::Zero();
        for (const Vec2& p : uv) centroid += p / count;
        std::vector<Vec2> dented = uv;
        dented[k] = mid + 0.3 * (centroid - mid);
        const bool reflex = [&] {
            const Vec2 e1 = dented[k] - dented[(k + count - 1) % count];
            const Vec2 e2 = dented[(k + 1) % count] - dented[k];
            return e1.x() * e2.y() - e1.y() * e2.x() < -1e-6;
        }();
        if (!reflex) continue;
        ++reflex_named;
        EXPECT_EQ(RefusedField(TableRequest(origin, n, dented)),
                  "planes[0].polygon[" + std::to_string(k) + "]");
    }
    EXPECT_GT(reflex_named, 50);

    std::vector<Vec2> star;
    for (int k = 0; k < 5; ++k) {
        const double t = 2.0 * std::numbers::pi * (2 * k) / 5;
        star.emplace_back(std::cos(t), std::sin(t));
    }
    const std::string star_field =
        RefusedField(TableRequest(Vec3(0, 0.8, -1), Vec3::UnitY(), star));
    EXPECT_TRUE(star_field.starts_with("planes[0].polygon")) << star_field;

    // The message says what the polygon must be.
    PlanRequest r = TableRequest(Vec3(0, 0.8, -1), Vec3::UnitY(),
                                 {{0, 0}, {0, 1}, {1, 1}, {1, 0}});  // clockwise about +y
    const auto plan = PlanShadowMaps(r);
    ASSERT_FALSE(plan.ok());
    EXPECT_NE(plan.error().reason.find("counter-clockwise"), std::string::npos)
        << plan.error().Message();
    // A straight angle (a vertex on the edge between its neighbours) keeps it convex.
    EXPECT_EQ(RefusedField(TableRequest(Vec3(0, 0.8, -1), Vec3::UnitY(),
                                        {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}})),
              "accepted");
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


// The crop snaps images within 1e-6 lixel past an integer onto it, so a needed ray can image
// just past the needed rectangle's edge. Without a guard band the lookup's half-open test then
// refuses a ray the map was made to hold (and no later map may hold it); with one, the lookup
// rectangle reaches kLookupMargin into the band and takes it.
TEST(Lookup, NeededRaysSnappedOntoTheRectanglesEdgeAreAccepted) {
    const Mat4 m = Mat4::Identity();  // lixel (x, y) = world (x, y) at z = 0, q = 1
    const std::vector<Vec4> needed = {Point(Vec3(0.25, 0.5, 0)),
                                      Point(Vec3(10.0000005, 3.5, 0))};  // snapped to x = 10
    for (const int guard : {0, kGuardLixels}) {
        CropOptions options;
        options.guard = guard;
        const auto crop = CropToNeededRays(m, needed, options);
        ASSERT_TRUE(crop.ok()) << crop.error().Message();
        ASSERT_EQ(crop->map.width, 10 + 2 * guard) << "the snap keeps the column out";
        PlannedMap planned;
        planned.map = crop->map;
        planned.lookup.guard = crop->guard;
        const bool accepted = LookupAccepts(planned, needed[1]);
        if (guard == 0) {
            EXPECT_FALSE(accepted) << "the defect a guard band removes";
        } else {
            EXPECT_TRUE(accepted);
            EXPECT_TRUE(LookupAccepts(planned, needed[0]));
            // The band itself, half a lixel past the needed rectangle, is not looked up.
            EXPECT_FALSE(LookupAccepts(planned, Point(Vec3(10.75, 3.5, 0))));
        }
    }
}

// Every planned map's needed rays are accepted by its own lookup test (its needed polygon's
// vertices, which lie on the crop's edges) over random rooms.
TEST(Lookup, EveryPlaneMapAcceptsItsNeededPolygonsVertices) {
    std::mt19937_64 rng(90210);
    int checked = 0;
    for (int i = 0; i < 300; ++i) {
        const testing::Configuration c = testing::RandomConfiguration(rng);
        PlanRequest r;
        r.viewer = c.viewer;
        r.viewport = c.viewport;
        r.light = c.light;
        r.scene_bounds = c.bounds;
        r.planes = {PlaneOfInterest{"plane", c.plane, {}}};
        r.lixel_budget = 1024 * 1024;
        const auto plan = PlanShadowMaps(r);
        if (!plan.ok()) continue;
        for (const PlannedMap& m : plan->maps) {
            if (m.role != MapRole::kPlane) continue;
            EXPECT_EQ(m.lookup.guard, kGuardLixels);
            for (const Vec3& v : m.needed_polygon) {
                const Vec4 p = m.map.matrix * Point(v);
                EXPECT_TRUE(LookupAccepts(m, Point(v)))
                    << "configuration " << i << ": vertex at lixel " << p.x() / p.w() << ", "
                    << p.y() / p.w() << " of " << m.map.width << " x " << m.map.height;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 300);
}

}  // namespace
}  // namespace lixel
