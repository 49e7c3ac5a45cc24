// Tests for lixel/solver/footprint.h (casters' footprints in a plane map's lixels, their
// rectangles) and for the scheduler's plane maps only where a shadow can fall.
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/footprint.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/scheduler.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Box;
using testing::Uniform;

// The floor map of the paper's room at one lixel per pixel, with its needed image.
struct FloorMap {
    testing::Configuration c = testing::FloorWallConfiguration();
    LightMap map;
    std::vector<Vec2> needed;
};

FloorMap MakeFloorMap(const Vec4& light) {
    FloorMap f;
    f.c.light = light;
    PlaneMapRequest request;
    request.input = f.c.Input();
    request.bounds = f.c.bounds;
    auto solved = SolvePlaneMap(request);
    EXPECT_TRUE(solved.ok()) << solved.error().Message();
    f.map = solved->crop.map;
    std::vector<Vec2> images;
    for (const Vec3& v : solved->needed_polygon) {
        const Vec4 h = f.map.matrix * Point(v);
        images.push_back({h.x() / h.w(), h.y() / h.w()});
    }
    f.needed = ConvexHull2d(images);
    return f;
}

bool Inside(const std::vector<Vec2>& polygon, const Vec2& p, double slack) {
    if (polygon.size() < 3) return false;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vec2 a = polygon[i];
        const Vec2 b = polygon[(i + 1) % polygon.size()];
        const Vec2 e = b - a;
        const double cross = e.x() * (p.y() - a.y()) - e.y() * (p.x() - a.x());
        if (cross < -slack * e.norm()) return false;
    }
    return true;
}

Vec2 Image(const LightMap& map, const Vec3& x) {
    const Vec4 h = map.matrix * Point(x);
    return {h.x() / h.w(), h.y() / h.w()};
}

// Where the light's ray through x meets the floor y = 0, or nothing when it goes up or along.
std::optional<Vec3> ShadowOnFloor(const Vec4& light, const Vec3& x) {
    const Vec3 d = light.w() == 0.0 ? Vec3(-light.head<3>()) : Vec3(x - light.head<3>());
    if (!(d.y() < 0.0)) return std::nullopt;
    return Vec3(x - (x.y() / d.y()) * d);
}

// An independent derivation: every point of the caster's box between the floor and the light
// casts its shadow at the floor point its light ray reaches; that point's image lies in the
// footprint whenever it lies in the needed image (0.01 lixel of rounding).
TEST(Footprint, HoldsTheShadowOfEveryPointOfRandomCasters) {
    std::mt19937_64 rng(12351);
    int checked = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const bool directional = trial % 3 == 0;
        const Vec4 light =
            directional ? Direction(Vec3(Uniform(rng, -1, 1), Uniform(rng, 0.2, 1), Uniform(rng, -1, 1)))
                        : Point(Vec3(Uniform(rng, -8, 8), Uniform(rng, 0.5, 9), Uniform(rng, -4, 9)));
        const FloorMap f = MakeFloorMap(light);
        // Boxes on, above, across the light's level and through the floor.
        const Vec3 centre(Uniform(rng, -8, 8), Uniform(rng, -0.5, 8), Uniform(rng, -4, 9));
        const Vec3 half(Uniform(rng, 0.05, 2), Uniform(rng, 0.05, 2), Uniform(rng, 0.05, 2));
        const Aabb box{centre - half, centre + half};
        const std::vector<Vec2> footprint = FootprintImage(
            f.map.matrix, Vec4(0, 1, 0, 0), light, ConvexPolytope::FromBox(box), f.needed);
        for (int k = 0; k < 400; ++k) {
            const Vec3 x(Uniform(rng, box.min.x(), box.max.x()),
                         Uniform(rng, box.min.y(), box.max.y()),
                         Uniform(rng, box.min.z(), box.max.z()));
            if (x.y() < 0.0) continue;  // under the floor: casts nothing onto it
            const auto y = ShadowOnFloor(light, x);
            if (!y) continue;
            const Vec4 h = f.map.matrix * Point(*y);
            if (!(h.w() > 0.0)) continue;  // behind the viewer
            const Vec2 p(h.x() / h.w(), h.y() / h.w());
            if (!Inside(f.needed, p, -0.01)) continue;  // not needed (0.01 lixel inside)
            ++checked;
            ASSERT_TRUE(Inside(footprint, p, 0.01))
                << "trial " << trial << ": point " << x.transpose() << " shadows "
                << y->transpose() << " at lixel " << p.transpose() << " outside its footprint";
        }
    }
    EXPECT_GT(checked, 10000);
}

// And it is tight: a box well between the floor and a point light has its footprint exactly
// the hull of its corners' shadows, clipped to the needed image.
TEST(Footprint, IsTheHullOfTheCornersShadowsForABoxBelowThePointLight) {
    const Vec4 light = Point(Vec3(4.0, 9.0, 3.0));
    const FloorMap f = MakeFloorMap(light);
    const Aabb box{Vec3(-1, 0.5, -2), Vec3(0, 1.5, -1)};
    const auto footprint = FootprintImage(f.map.matrix, Vec4(0, 1, 0, 0), light,
                                          ConvexPolytope::FromBox(box), f.needed);
    std::vector<Vec2> shadows;
    for (const Vec4& corner : BoxCorners(box)) {
        shadows.push_back(Image(f.map, *ShadowOnFloor(light, corner.head<3>())));
    }
    const std::vector<Vec2> hull = ConvexHull2d(shadows);
    ASSERT_GE(footprint.size(), 3u);
    for (const Vec2& p : footprint) EXPECT_TRUE(Inside(hull, p, 1e-6)) << p.transpose();
    for (const Vec2& p : hull) EXPECT_TRUE(Inside(footprint, p, 1e-6)) << p.transpose();
    // The facet tests' slack moves edges by about 1e-9 lixel per 1000 lixels of coordinate.
    EXPECT_NEAR(PolygonArea2d(ConvexHull2d(footprint)), PolygonArea2d(hull),
                1e-6 * PolygonArea2d(hull));
}

TEST(Footprint, NamedStiffCases) {
    const Vec4 light = Point(Vec3(4.0, 9.0, 3.0));
    const FloorMap f = MakeFloorMap(light);
    const Vec4 floor(0, 1, 0, 0);
    const auto footprint = [&](const Aabb& box, const Vec4& l) {
        return FootprintImage(f.map.matrix, floor, l, ConvexPolytope::FromBox(box), f.needed);
    };
    // Under the floor: no shadow on it.
    EXPECT_TRUE(footprint({Vec3(-1, -2, -1), Vec3(1, -0.5, 1)}, light).empty());
    // Wholly above the light: its rays go up.
    EXPECT_TRUE(footprint({Vec3(3, 10, 2), Vec3(5, 11, 4)}, light).empty());
    // The light inside the box: every ray is the box's, so all of the needed image.
    EXPECT_EQ(footprint({Vec3(3, 8, 2), Vec3(5, 10, 4)}, light), f.needed);
    // The light on the box's top face, and at one of its corners: still everything below.
    EXPECT_FALSE(footprint({Vec3(3, 8, 2), Vec3(5, 9, 4)}, light).empty());
    EXPECT_FALSE(footprint({Vec3(3, 8, 2), Vec3(4, 9, 3)}, light).empty());
    // Resting on the floor: its base is in its own shadow.
    const Aabb crate{Vec3(-1, 0, -2), Vec3(0, 1, -1)};
    const auto rested = footprint(crate, light);
    ASSERT_GE(rested.size(), 3u);
    EXPECT_TRUE(Inside(rested, Image(f.map, Vec3(-0.5, 0, -1.5)), 1e-6));
    // Straddling the light's level: its shadow runs to the horizon, and the needed image stops
    // it there.
    const auto tall = footprint({Vec3(0, 0, -4), Vec3(1, 12, -3)}, light);
    EXPECT_GE(tall.size(), 3u);
    // A directional light parallel to the floor: no ray reaches it.
    EXPECT_TRUE(footprint(crate, Direction(Vec3(1, 0, 0))).empty() ||
                footprint(crate, Direction(Vec3(1, 0, 0))) == f.needed);
}

TEST(Footprint, RectanglesCoverTheirInputsWithinTheCountAndMergeOnlyWhenCheaperOrForced) {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<LixelRect> rects;
        const int n = 1 + static_cast<int>(Uniform(rng, 0, 40));
        for (int i = 0; i < n; ++i) {
            const int x = static_cast<int>(Uniform(rng, 0, 1000));
            const int y = static_cast<int>(Uniform(rng, 0, 1000));
            rects.push_back({x, y, x + 1 + static_cast<int>(Uniform(rng, 0, 200)),
                             y + 1 + static_cast<int>(Uniform(rng, 0, 200))});
        }
        const int limit = 1 + trial % 4;
        const auto merged = MergeRects(rects, 2, limit);
        ASSERT_LE(merged.size(), static_cast<size_t>(limit));
        ASSERT_FALSE(merged.empty());
        for (const LixelRect& r : rects) {
            const bool covered = std::any_of(merged.begin(), merged.end(), [&](const LixelRect& m) {
                return m.x0 <= r.x0 && m.y0 <= r.y0 && m.x1 >= r.x1 && m.y1 >= r.y1;
            });
            ASSERT_TRUE(covered) << "trial " << trial;
        }
    }
    // Two far apart stay two; one inside another becomes one.
    EXPECT_EQ(MergeRects({{0, 0, 10, 10}, {500, 500, 510, 510}}, 2, 4).size(), 2u);
    EXPECT_EQ(MergeRects({{0, 0, 100, 100}, {10, 10, 20, 20}}, 2, 4),
              (std::vector<LixelRect>{{0, 0, 100, 100}}));
    // Snapping: an image 1e-7 past an integer does not cost a row; a point still gets a lixel.
    EXPECT_EQ(RectAround({Vec2(2.0000001, 3), Vec2(5.9999999, 4.5)}), (LixelRect{2, 3, 6, 5}));
    EXPECT_EQ(RectAround({Vec2(7, 7)}), (LixelRect{7, 7, 8, 8}));
}

// The corners' route against the clips' (FootprintImage), on seeded casters around the floor
// map of random lights, over a region the size of the viewport less a lixel and a half: kInside gives a
// rectangle that holds the clips' (the caster lies in its bounds), the same one for a box wholly
// above the floor (both routes find the same points, up to rounding), and at most one lixel
// larger on a side for a box that reaches into the thickening under the floor; kOutside only
// where the clips leave nothing of the caster in the region; every case decided somewhere.
TEST(Footprint, CornersDecideTheRectangleAsTheClipsDo) {
    std::mt19937_64 rng(8128);
    const Vec4 floor(0, 1, 0, 0);
    const double thickness = 1e-6 * 40.0;
    int inside = 0, outside = 0, undecided = 0, equal = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const bool directional = trial % 4 == 0;
        const Vec4 light = directional ? Direction(Vec3(Uniform(rng, -1, 1), Uniform(rng, 0.2, 1),
                                                        Uniform(rng, -1, 1)))
                                       : Point(Vec3(Uniform(rng, -8, 8), Uniform(rng, 2, 12),
                                                    Uniform(rng, -4, 9)));
        const FloorMap f = MakeFloorMap(light);
        const Eigen::Vector4d region(1.5, 1.5, f.c.viewport.width - 1.5,
                                     f.c.viewport.height - 1.5);
        const std::vector<Vec2> corners = {Vec2(region[0], region[1]), Vec2(region[2], region[1]),
                                           Vec2(region[2], region[3]), Vec2(region[0], region[3])};
        for (int k = 0; k < 25; ++k) {
            // Boxes standing on the floor (thickened under it), floating, and across the light.
            const Vec3 centre(Uniform(rng, -12, 12), 0.0, Uniform(rng, -6, 14));
            const Vec3 half(Uniform(rng, 0.02, 1.5), Uniform(rng, 0.02, 1.5),
                            Uniform(rng, 0.02, 1.5));
            const int kind = k % 3;
            const double bottom = kind == 0 ? -thickness : Uniform(rng, 0.0, kind == 1 ? 3 : 11);
            const Aabb box{Vec3(centre.x() - half.x(), bottom, centre.z() - half.z()),
                           Vec3(centre.x() + half.x(), bottom + 2 * half.y(),
                                centre.z() + half.z())};
            const ConvexPolytope caster = ConvexPolytope::FromBox(box);
            const CornerFootprint decided =
                CornerFootprintOf(f.map.matrix, floor, light, caster.Bounds(), thickness, region);
            const std::vector<Vec2> clipped =
                FootprintImage(f.map.matrix, floor, light, caster, corners);
            SCOPED_TRACE("trial " + std::to_string(trial) + " box " + std::to_string(k));
            if (decided.kind == CornerFootprint::Kind::kUndecided) {
                ++undecided;
                continue;
            }
            if (decided.kind == CornerFootprint::Kind::kOutside) {
                ++outside;
                EXPECT_TRUE(clipped.empty()) << clipped.size() << " points";
                continue;
            }
            ++inside;
            ASSERT_FALSE(clipped.empty());
            const LixelRect fast = RectAround(decided.images);
            const LixelRect exact = RectAround(clipped);
            EXPECT_EQ(fast.Union(exact), fast) << "the corners' rectangle holds the clips'";
            if (box.min.y() > thickness) {
                EXPECT_EQ(fast, exact);
                equal += fast == exact;
            } else {
                EXPECT_LE(exact.x0 - fast.x0, 1);
                EXPECT_LE(exact.y0 - fast.y0, 1);
                EXPECT_LE(fast.x1 - exact.x1, 1);
                EXPECT_LE(fast.y1 - exact.y1, 1);
            }
        }
    }
    EXPECT_GT(inside, 1000);
    EXPECT_GT(outside, 500);
    EXPECT_GT(undecided, 500);
    EXPECT_GT(equal, 500);
}

// A caster wholly past a side of the light cone over a region (RegionCone) casts nothing into
// it, checked against an independent derivation: no point of its box between the floor and the
// light shadows a floor point whose image lies in the region. The clips agree: they find nothing,
// or, where the caster's own cone is degenerate (not pointed or flat), the whole region, which
// the cone's test leaves out.
TEST(Footprint, CastersPastASideOfTheRegionsLightConeCastNothingIntoIt) {
    std::mt19937_64 rng(4099);
    const Vec4 floor(0, 1, 0, 0);
    int outside = 0, kept = 0, sampled = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const bool directional = trial % 3 == 0;
        const Vec4 light =
            directional
                ? Direction(Vec3(Uniform(rng, -1, 1), Uniform(rng, 0.2, 1), Uniform(rng, -1, 1)))
                : Point(Vec3(Uniform(rng, -8, 8), Uniform(rng, 0.5, 9), Uniform(rng, -4, 9)));
        const FloorMap f = MakeFloorMap(light);
        // A random part of the map's rectangle, as a footprint split's lookup rectangle.
        const double w = f.c.viewport.width, h = f.c.viewport.height;
        const double x0 = Uniform(rng, 0, 0.7 * w), y0 = Uniform(rng, 0, 0.7 * h);
        const Eigen::Vector4d region(x0, y0, Uniform(rng, x0 + 1, w), Uniform(rng, y0 + 1, h));
        const std::vector<PlaneTest> cone = RegionCone(f.map.matrix, floor, light, region);
        ASSERT_FALSE(cone.empty());
        const std::vector<Vec2> corners = {Vec2(region[0], region[1]), Vec2(region[2], region[1]),
                                           Vec2(region[2], region[3]), Vec2(region[0], region[3])};
        for (int k = 0; k < 30; ++k) {
            // Boxes on, above, across the light's level, through the floor and behind the eye.
            const Vec3 centre(Uniform(rng, -20, 20), Uniform(rng, -0.5, 10), Uniform(rng, -10, 20));
            const Vec3 half(Uniform(rng, 0.02, 2), Uniform(rng, 0.02, 2), Uniform(rng, 0.02, 2));
            const Aabb box{centre - half, centre + half};
            const ConvexPolytope caster = ConvexPolytope::FromBox(box);
            if (!OutsideRegionCone(caster.Bounds(), cone)) {
                ++kept;
                continue;
            }
            ++outside;
            const std::vector<Vec2> clipped =
                FootprintImage(f.map.matrix, floor, light, caster, corners);
            EXPECT_TRUE(clipped.empty() || clipped == corners) << clipped.size() << " points";
            for (int s = 0; s < 200; ++s) {
                const Vec3 x(Uniform(rng, box.min.x(), box.max.x()),
                             Uniform(rng, box.min.y(), box.max.y()),
                             Uniform(rng, box.min.z(), box.max.z()));
                if (x.y() < 0.0) continue;
                if (!directional && x.y() >= light.y() / light.w()) continue;  // above the light
                const auto y = ShadowOnFloor(light, x);
                if (!y) continue;
                const Vec4 q = f.map.matrix * Point(*y);
                if (!(q.w() > 0.0)) continue;
                ++sampled;
                const Vec2 p(q.x() / q.w(), q.y() / q.w());
                ASSERT_FALSE(p.x() >= region[0] && p.x() <= region[2] && p.y() >= region[1] &&
                             p.y() <= region[3])
                    << "trial " << trial << ": point " << x.transpose() << " shadows lixel "
                    << p.transpose() << " inside the region";
            }
        }
    }
    EXPECT_GT(outside, 2000);
    EXPECT_GT(kept, 300);
    EXPECT_GT(sampled, 100000);
}

PlanRequest Room(std::int64_t budget) { return testing::FloorWallRoomRequest(budget); }

// The paper's room at a budget of one lixel per viewer pixel: whole plane maps need a scale
// below 1; the footprints fit at scale 1, every rectangle on the grid of its plane's one matrix.
TEST(SchedulerFootprints, OneLixelPerPixelKeepsScaleOneInThePapersRoom) {
    const PlanRequest request = Room(1024 * 1024);
    PlanRequest whole = request;
    whole.footprints.enabled = false;
    const auto whole_plan = PlanShadowMaps(whole);
    ASSERT_TRUE(whole_plan.ok()) << whole_plan.error().Message();
    EXPECT_LT(whole_plan->plane_scale, 1.0);

    const auto plan = PlanShadowMaps(request);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_EQ(plan->plane_scale, 1.0);
    EXPECT_LE(plan->total_lixels, request.lixel_budget);
    int rectangles = 0;
    for (size_t i = 0; i < plan->maps.size(); ++i) {
        const PlannedMap& m = plan->maps[i];
        if (m.role != MapRole::kPlane) continue;
        EXPECT_EQ(m.scale, 1.0) << m.name;
        if (m.lookup.unshadowed) {
            EXPECT_EQ(m.lixels, 0) << m.name;
            EXPECT_TRUE(m.passes.empty()) << m.name;
            continue;
        }
        if (!m.footprint) continue;
        ++rectangles;
        // The plane's unshadowed entry follows its rectangles; each rectangle is its matrix
        // moved by whole lixels (the same z and w rows, x and y rows plus integers times w).
        auto lit = std::find_if(plan->maps.begin() + static_cast<std::ptrdiff_t>(i),
                                plan->maps.end(), [&](const PlannedMap& o) {
                                    return o.plane_index == m.plane_index && o.lookup.unshadowed;
                                });
        ASSERT_NE(lit, plan->maps.end()) << m.name;
        const Mat4& a = m.map.matrix;
        const Mat4& b = lit->map.matrix;
        EXPECT_EQ(a.row(2), b.row(2));
        EXPECT_EQ(a.row(3), b.row(3));
        for (int row = 0; row < 2; ++row) {
            const RowVec4 shift = a.row(row) - b.row(row);
            const double k = shift(3) / b(3, 3);
            EXPECT_NEAR(k, std::round(k), 1e-9) << m.name;
            EXPECT_LE((shift - std::round(k) * b.row(3)).cwiseAbs().maxCoeff(),
                      1e-12 * b.cwiseAbs().maxCoeff())
                << m.name;
        }
    }
    EXPECT_GE(rectangles, 1);
    EXPECT_LE(rectangles, request.footprints.max_per_plan);
}

TEST(SchedulerFootprints, RectangleLimitsHoldAndBadLimitsAreRefusedByName) {
    for (int per_plan = 1; per_plan <= 4; ++per_plan) {
        PlanRequest r = Room(512 * 512);
        r.footprints.max_per_plan = per_plan;
        r.footprints.max_per_plane = 1;
        const auto plan = PlanShadowMaps(r);
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        int floor = 0, total = 0;
        for (const PlannedMap& m : plan->maps) {
            total += m.footprint ? 1 : 0;
            floor += m.footprint && m.plane_index == 0 ? 1 : 0;
        }
        EXPECT_LE(total, per_plan);
        EXPECT_LE(floor, 1);
    }
    for (const int bad : {0, -1, kMaxFootprintRectangles + 1}) {
        PlanRequest r = Room(512 * 512);
        r.footprints.max_per_plane = bad;
        auto plan = PlanShadowMaps(r);
        ASSERT_FALSE(plan.ok());
        EXPECT_EQ(plan.error().field, "footprints.max_per_plane");
        r = Room(512 * 512);
        r.footprints.max_per_plan = bad;
        plan = PlanShadowMaps(r);
        ASSERT_FALSE(plan.ok());
        EXPECT_EQ(plan.error().field, "footprints.max_per_plan");
    }
    // A light inside a caster's box: the floor's footprint is all of it (one rectangle no
    // cheaper than the whole map), never a crash or a map past the budget.
    PlanRequest inside = Room(512 * 512);
    inside.objects.push_back(Box("lamp shade", Vec3(3.5, 8.5, 2.5), Vec3(4.5, 9.5, 3.5)));
    const auto plan = PlanShadowMaps(inside);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    EXPECT_LE(plan->total_lixels, inside.lixel_budget);
}

// Planning is a function of its request: the same request gives the same plan, bit for bit.
TEST(SchedulerFootprints, PlansAreDeterministic) {
    const PlanRequest r = Room(1024 * 1024);
    const auto a = PlanShadowMaps(r);
    const auto b = PlanShadowMaps(r);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->maps.size(), b->maps.size());
    for (size_t i = 0; i < a->maps.size(); ++i) {
        EXPECT_EQ(a->maps[i].map.matrix, b->maps[i].map.matrix);
        EXPECT_EQ(a->maps[i].map.width, b->maps[i].map.width);
        EXPECT_EQ(a->maps[i].map.height, b->maps[i].map.height);
        EXPECT_EQ(a->maps[i].expected_pixels, b->maps[i].expected_pixels);
    }
}

}  // namespace
}  // namespace lixel
