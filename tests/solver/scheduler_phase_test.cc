// Plane maps in phase with the viewer's pixels (issue 26): at scale 1 a plane map's lixel grid
// is the viewer's pixel grid on the plane, so every pixel centre on the plane images to a lixel
// centre; a plane map's lookup stops at the line where a plane hiding its back side cuts it, so
// that plane's own map serves the points just past the line; and a budget too small for every
// plane map at scale 1 keeps as many planes at scale 1 as it can (ScalePolicy).
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/scheduler.h>

#include <cmath>
#include <numbers>
#include <random>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Uniform;

constexpr double kDegree = std::numbers::pi / 180.0;

// The paper's room (floor y = 0, wall z = -5, its boxes) seen from a random eye in front of the
// wall, lit by a random point light above the room or a directional light from the front, with
// a budget that holds every plane map at scale 1.
PlanRequest RandomRoom(std::mt19937_64& rng, int index) {
    PlanRequest r;
    const double eye_x = Uniform(rng, -5, 5);
    const double eye_y = Uniform(rng, 1.5, 5);
    const Vec3 eye(eye_x, eye_y, Uniform(rng, 4, 8));
    const double target_x = Uniform(rng, -2, 2);
    const double target_y = Uniform(rng, 0, 1.5);
    const Vec3 target(target_x, target_y, Uniform(rng, -4, 0));
    const double fovy = Uniform(rng, 40, 80) * kDegree;
    r.viewer = Perspective(fovy, 1.0, 0.1, 60.0) * LookAt(eye, target, Vec3::UnitY());
    r.viewport = {256, 256};
    const double a = Uniform(rng, -1, 1);
    const double b = Uniform(rng, 0.4, 1);
    const double c = Uniform(rng, 0.1, 1);
    r.light = index % 3 == 0 ? Vec4(a, b, c, 0.0) : Point(Vec3(6 * a, 6 + 4 * b, 7 * c));
    r.objects = testing::FloorWallRoomObjects();
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}}, {"wall", Vec4(0, 0, 1, 5), {}}};
    r.lixel_budget = 4 * 256 * 256;
    return r;
}

// The world point (homogeneous) where the viewer's ray through window point (x, y) meets plane
// `p`: the line through the ray's near and far clip points, X = (p.B) A - (p.A) B.
Vec4 OnPlaneAt(const PlanRequest& r, const Vec4& p, double x, double y) {
    const Mat4 inverse = r.viewer.inverse();
    const double nx = 2.0 * x / r.viewport.width - 1.0;
    const double ny = 2.0 * y / r.viewport.height - 1.0;
    const Vec4 a = inverse * Vec4(nx, ny, 0.0, 1.0);
    const Vec4 b = inverse * Vec4(nx, ny, 1.0, 1.0);
    return p.dot(b) * a - p.dot(a) * b;
}

// Largest distance, in lixels, from a pixel centre's image to its lixel's centre over the plane
// maps at scale 1, sampled at every 7th pixel of the view whose ray meets the plane in front of
// the viewer and which the map's lookup accepts.
double WorstCentreOffset(const PlanRequest& r, const Plan& plan, int& sampled) {
    double worst = 0.0;
    for (const PlannedMap& m : plan.maps) {
        if (m.role != MapRole::kPlane || m.scale != 1.0) continue;
        const Vec4 plane = r.planes[m.plane_index].plane;
        for (int y = 0; y < r.viewport.height; y += 7) {
            for (int x = 0; x < r.viewport.width; x += 7) {
                Vec4 X = OnPlaneAt(r, plane, x + 0.5, y + 0.5);
                if (X.w() == 0.0) continue;
                X /= X.w();
                const Vec4 clip = r.viewer * X;
                if (!(clip.w() > 0.0) || !LookupAccepts(m, X)) continue;
                const Vec4 l = m.map.matrix * X;
                for (const double v : {l.x() / l.w(), l.y() / l.w()}) {
                    worst = std::max(worst, std::abs(v - std::floor(v) - 0.5));
                }
                ++sampled;
            }
        }
    }
    return worst;
}

TEST(SchedulerPhase, PixelCentresOnAPlaneImageToLixelCentresAtScaleOne) {
    std::mt19937_64 rng(2604);
    int sampled = 0;
    int drifting_free = 0;  // rooms whose free twists leave the grid out of phase
    for (int i = 0; i < 60; ++i) {
        PlanRequest r = RandomRoom(rng, i);
        const auto plan = PlanShadowMaps(r);
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        for (const PlannedMap& m : plan->maps) {
            if (m.role != MapRole::kPlane) continue;
            ASSERT_EQ(m.scale, 1.0) << "room " << i << " " << m.name;
            const double quarters = m.twist_radians / (std::numbers::pi / 2.0);
            EXPECT_NEAR(quarters, std::round(quarters), 1e-12) << "room " << i << " " << m.name;
        }
        // Double rounding of the solve and the crop: far below a lixel (1e-6 of it).
        EXPECT_LE(WorstCentreOffset(r, *plan, sampled), 1e-6) << "room " << i;

        // The paper's twists, for contrast: the same rooms drift off the pixel centres.
        r.in_phase = false;
        const auto free = PlanShadowMaps(r);
        ASSERT_TRUE(free.ok()) << free.error().Message();
        int ignored = 0;
        drifting_free += WorstCentreOffset(r, *free, ignored) > 0.01;
    }
    EXPECT_GT(sampled, 10000);
    std::printf("[ phase    ] %d pixel centres sampled; free twists out of phase in %d of 60 "
                "rooms\n", sampled, drifting_free);
    EXPECT_GE(drifting_free, 30);
}

// A wall point just above the floor has a light ray that meets the floor's plane behind the
// wall. With the floor's polygon ending at the wall (floor and wall are quads, so the scene's
// box ends there), no floor map may accept it: the floor's lixels sample the wall at a grazing
// angle there. The wall's own map or its unshadowed entry serves it.
TEST(SchedulerPhase, NoFloorMapTakesTheWallsPointsAboveTheMeetingLine) {
    std::mt19937_64 rng(2605);
    int checked = 0;
    for (int i = 0; i < 60; ++i) {
        PlanRequest r = RandomRoom(rng, i);
        r.objects[0] = testing::Box("floor", Vec3(-10, 0, -5), Vec3(10, 0, 10));
        r.objects[1] = testing::Box("wall", Vec3(-10, 0, -5), Vec3(10, 8, -5));
        const auto plan = PlanShadowMaps(r);
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        for (int k = 0; k < 400; ++k) {
            const double x = Uniform(rng, -8, 8);  // sequenced: one point on every compiler
            const Vec4 X = Point(Vec3(x, Uniform(rng, 1e-4, 0.2), -5.0));
            const Vec4 clip = r.viewer * X;
            if (!(clip.w() > 0.0) || (clip.head<2>() / clip.w()).cwiseAbs().maxCoeff() > 1.0) {
                continue;
            }
            const int m = LookupMap(*plan, X);
            ASSERT_GE(m, 0) << "room " << i << ": no map takes wall point " << X.transpose();
            EXPECT_EQ(plan->maps[m].plane_index, 1)
                << "room " << i << ": " << plan->maps[m].name << " takes wall point "
                << X.head<3>().transpose();
            ++checked;
        }
    }
    EXPECT_GT(checked, 2000);
}

// A budget that leaves `planes` lixels to the plane maps of a plan like `roomy`: the fallback's
// floor is min(fallback_floor, budget / 2) when there is a fallback (scheduler.h).
std::int64_t BudgetLeaving(const PlanRequest& r, const Plan& roomy, std::int64_t planes) {
    bool fallback = false;
    for (const PlannedMap& m : roomy.maps) fallback |= m.role != MapRole::kPlane;
    return planes + (fallback ? std::min(r.fallback_floor, planes) : 0);
}

// Priority: the planes at scale 1 come first in priority order, the rest share one scale below
// it, and the budget holds; uniform: one scale for all; in phase: one scale 1/k. Every plane
// map says why it got its scale. Per room (lit from low in front, so the wall has shadows too),
// budgets that hold the floor's maps at scale 1 and 5 %, 25 % or 50 % of the wall's, and a random
// one of 1/64 to 1/2 lixel per pixel.
void ExpectPoliciesHold(PlanRequest r, int room, bool& floor_held_alone) {
    const auto priority = PlanShadowMaps(r);
    ASSERT_TRUE(priority.ok()) << priority.error().Message();
    r.scale_policy = ScalePolicy::kUniform;
    const auto uniform = PlanShadowMaps(r);
    ASSERT_TRUE(uniform.ok()) << uniform.error().Message();
    r.scale_policy = ScalePolicy::kInPhase;
    const auto phased = PlanShadowMaps(r);
    ASSERT_TRUE(phased.ok()) << phased.error().Message();

    int last_held = -1, first_lowered = 1 << 30;
    for (const PlannedMap& m : priority->maps) {
        if (m.role != MapRole::kPlane) continue;
        EXPECT_FALSE(m.scale_reason.empty()) << "room " << room << " " << m.name;
        if (m.scale == 1.0) {
            last_held = std::max(last_held, m.plane_index);
        } else {
            first_lowered = std::min(first_lowered, m.plane_index);
            EXPECT_EQ(m.scale, priority->plane_scale) << "room " << room << " " << m.name;
        }
    }
    EXPECT_LT(last_held, first_lowered) << "room " << room << ": held planes lead";
    double uniform_scale = -1.0;
    for (const PlannedMap& m : uniform->maps) {
        if (m.role != MapRole::kPlane) continue;
        if (uniform_scale < 0.0) uniform_scale = m.scale;
        EXPECT_EQ(m.scale, uniform_scale) << "room " << room << " " << m.name;
    }
    for (const PlannedMap& m : phased->maps) {
        if (m.role != MapRole::kPlane) continue;
        const double k = 1.0 / m.scale;
        EXPECT_NEAR(k, std::round(k), 1e-9) << "room " << room << " " << m.name;
    }
    // A plane map lowered by the budget names the policy that lowered it.
    for (const auto& [p, policy] : {std::pair{&*priority, "scale_policy priority"},
                                    std::pair{&*uniform, "scale_policy uniform"},
                                    std::pair{&*phased, "scale_policy in_phase"}}) {
        EXPECT_LE(p->total_lixels, r.lixel_budget) << "room " << room;
        for (const PlannedMap& m : p->maps) {
            if (m.role != MapRole::kPlane || m.scale >= 1.0) continue;
            EXPECT_NE(m.scale_reason.find(policy), std::string::npos)
                << "room " << room << " " << m.name << ": " << m.scale_reason;
        }
    }
    floor_held_alone |= last_held == 0 && first_lowered == 1 && uniform_scale < 1.0;
}

TEST(SchedulerPhase, TheBudgetPolicyKeepsTheLeadingPlanesAtScaleOne) {
    std::mt19937_64 rng(2606);
    int held_rooms = 0;  // rooms where priority keeps the floor at 1 and uniform keeps none
    for (int i = 0; i < 60; ++i) {
        PlanRequest r = RandomRoom(rng, i);
        // A low light in front of the room: the boxes shadow the wall too.
        const double side = Uniform(rng, -0.5, 0.5);
        r.light = Vec4(side, Uniform(rng, 0.25, 0.6), 1.0, 0.0);
        const auto roomy = PlanShadowMaps(r);
        ASSERT_TRUE(roomy.ok()) << roomy.error().Message();
        std::int64_t floor = 0, wall = 0;
        for (const PlannedMap& m : roomy->maps) {
            floor += m.plane_index == 0 ? m.lixels : 0;
            wall += m.plane_index == 1 ? m.lixels : 0;
        }
        bool held = false;
        for (const double share : {0.05, 0.25, 0.5}) {
            r.lixel_budget = BudgetLeaving(
                r, *roomy, floor + static_cast<std::int64_t>(share * static_cast<double>(wall)));
            ExpectPoliciesHold(r, i, held);
        }
        r.lixel_budget = static_cast<std::int64_t>(256 * 256 * std::pow(2.0, Uniform(rng, -6, -1)));
        ExpectPoliciesHold(r, i, held);
        held_rooms += held;
    }
    std::printf("[ policy   ] the floor alone kept at scale 1 under priority, no plane under "
                "uniform, in %d of 60 rooms\n", held_rooms);
    EXPECT_GE(held_rooms, 10);
}

// The guard band gives way before the scale: a budget a lixel short of the plane maps with
// their bands keeps every plane map at scale 1 with a narrower band.
TEST(SchedulerPhase, AGuardBandNeverLowersTheScale) {
    std::mt19937_64 rng(2608);
    int narrowed = 0;
    for (int i = 0; i < 60; ++i) {
        PlanRequest r = RandomRoom(rng, i);
        const auto roomy = PlanShadowMaps(r);
        ASSERT_TRUE(roomy.ok()) << roomy.error().Message();
        std::int64_t planes = 0;
        for (const PlannedMap& m : roomy->maps) planes += m.role == MapRole::kPlane ? m.lixels : 0;
        if (planes == 0) continue;
        r.lixel_budget = BudgetLeaving(r, *roomy, planes - 1);
        const auto tight = PlanShadowMaps(r);
        ASSERT_TRUE(tight.ok()) << tight.error().Message();
        EXPECT_LE(tight->total_lixels, r.lixel_budget) << "room " << i;
        for (const PlannedMap& m : tight->maps) {
            if (m.role != MapRole::kPlane) continue;
            EXPECT_EQ(m.scale, 1.0) << "room " << i << " " << m.name;
            EXPECT_LT(m.lookup.guard, kGuardLixels) << "room " << i << " " << m.name;
            // Below 32^2 lixels the budget's own guard is under kGuardLixels already.
            if (r.lixel_budget < 32 * 32) continue;
            EXPECT_NE(m.scale_reason.find("guard band narrowed"), std::string::npos)
                << "room " << i << " " << m.name << ": " << m.scale_reason;
        }
        ++narrowed;
    }
    EXPECT_GE(narrowed, 40);
}

// A floor that crosses the back wall's plane (the wall's box is behind it) and only reaches a
// side wall's (the scene's box ends there) twists along the back wall's line, which cuts it,
// whatever the planes' order: the paper's twist (§3) with free twists on.
TEST(SchedulerPhase, TheFloorTwistsAlongTheWallItCrosses) {
    PlanRequest r;
    r.viewer = Perspective(60.0 * kDegree, 1.0, 0.1, 60.0) *
               LookAt(Vec3(2, 3, 6), Vec3(-4, 0.5, -3), Vec3::UnitY());
    r.viewport = {256, 256};
    r.light = Point(Vec3(2, 9, 4));
    r.objects = {testing::Box("floor", Vec3(-8, -0.1, -5.1), Vec3(8, 0, 8)),
                 testing::Box("wall", Vec3(-8, 0, -5.1), Vec3(8, 6, -5)),
                 testing::Box("side", Vec3(-8, 0, -5.1), Vec3(-8, 6, 8)),
                 testing::Box("cube", Vec3(-3, 0, -3), Vec3(-2, 1, -2))};
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}},
                {"side", Vec4(1, 0, 0, 8), {}},
                {"wall", Vec4(0, 0, 1, 5), {}}};
    r.lixel_budget = 4 * 256 * 256;
    r.in_phase = false;
    r.footprints.enabled = false;
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    const PlannedMap* floor = nullptr;
    for (const PlannedMap& m : plan->maps) {
        if (m.role == MapRole::kPlane && m.plane_index == 0) floor = &m;
    }
    ASSERT_NE(floor, nullptr);
    // Two points of the floor/back-wall line image to one lixel row.
    const Vec4 a = floor->map.matrix * Point(Vec3(-6, 0, -5));
    const Vec4 b = floor->map.matrix * Point(Vec3(4, 0, -5));
    EXPECT_NEAR(a.y() / a.w(), b.y() / b.w(), 1e-6 * std::abs(a.x() / a.w() - b.x() / b.w()));
}

TEST(SchedulerPhase, AnUnknownScalePolicyIsRefusedByName) {
    std::mt19937_64 rng(2607);
    PlanRequest r = RandomRoom(rng, 1);
    r.scale_policy = static_cast<ScalePolicy>(7);
    const auto plan = PlanShadowMaps(r);
    ASSERT_FALSE(plan.ok());
    EXPECT_EQ(plan.error().field, "scale_policy");
}

}  // namespace
}  // namespace lixel
