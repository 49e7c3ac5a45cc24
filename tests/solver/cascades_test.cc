// Tests for cascades.h and baseline_plan.h: the practical split scheme, cascades that hold what
// their slice needs within their share of the budget, the lookup that picks the cascade by view
// depth, and stabilization's promise (the texel grid stays fixed in the world as the camera
// turns and moves).
#include <gtest/gtest.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/cascades.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::FloorRoom;
using testing::RandomFloorRoom;
using testing::Uniform;

TEST(Cascades, PracticalSplitsFollowZhangEtAl) {
    std::mt19937_64 rng(2006);
    for (int trial = 0; trial < 1000; ++trial) {
        const double near = std::exp(Uniform(rng, -10.0, 5.0));
        const double far = near * std::exp(Uniform(rng, 0.01, 12.0));
        const int count = 1 + static_cast<int>(Uniform(rng, 0.0, 7.99));
        const double lambda = Uniform(rng, 0.0, 1.0);
        const std::vector<double> log_split = PracticalSplits(near, far, count, 1.0);
        const std::vector<double> uniform_split = PracticalSplits(near, far, count, 0.0);
        const std::vector<double> z = PracticalSplits(near, far, count, lambda);
        ASSERT_EQ(z.size(), static_cast<std::size_t>(count) + 1);
        EXPECT_EQ(z.front(), near);
        EXPECT_EQ(z.back(), far);
        const double ratio = std::pow(far / near, 1.0 / count);
        for (int i = 0; i < count; ++i) {
            EXPECT_LT(z[i], z[i + 1]);
            // Logarithmic: every slice has the same far / near; uniform: the same depth.
            EXPECT_NEAR(log_split[i + 1] / log_split[i], ratio, 1e-12 * ratio);
            EXPECT_NEAR(uniform_split[i + 1] - uniform_split[i], (far - near) / count,
                        1e-12 * far);
            EXPECT_NEAR(z[i], lambda * log_split[i] + (1.0 - lambda) * uniform_split[i],
                        1e-12 * far);
        }
    }
}

BaselineInput InputOf(const FloorRoom& room, std::int64_t budget) {
    BaselineInput input{room.c.viewer, room.c.viewport, room.c.light, budget};
    input.receivers = room.receivers;
    return input;
}

PlanRequest RequestOf(const FloorRoom& room, std::int64_t budget) {
    PlanRequest request;
    request.viewer = room.c.viewer;
    request.viewport = room.c.viewport;
    request.light = room.c.light;
    request.lixel_budget = budget;
    request.scene_bounds = room.c.bounds;
    for (const Aabb& box : room.receivers) request.objects.push_back(testing::Box("receiver", box.min, box.max));
    return request;
}

// View depth of world point x along the viewer's axis (the eye's distance along f).
double ViewDepth(const Mat4& viewer, const Vec3& x) {
    const RowVec4 w = viewer.row(3);
    return w.dot(Point(x)) / w.head<3>().norm();
}

// Over random floor rooms (both light kinds, 1 to 8 cascades, every λ): each cascade is a
// square of the side its even share of the budget buys, the cascades together stay within the
// budget, and every floor point the viewer sees goes, by the lookup rule alone, to the nearest
// cascade whose slice reaches its view depth, which holds it: its lixel inside the map and its
// stored depth in [0, 1].
TEST(Cascades, EveryVisibleFloorPointGoesToTheCascadeOfItsSliceWhichHoldsIt) {
    std::mt19937_64 rng(8);
    int stabilized = 0, tight = 0, points = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const FloorRoom room = RandomFloorRoom(rng);
        SCOPED_TRACE("trial " + std::to_string(trial));
        const std::int64_t budget =
            static_cast<std::int64_t>(std::exp(Uniform(rng, std::log(64.0 * 64), std::log(4096.0 * 4096))));
        CascadeOptions options;
        options.count = 1 + static_cast<int>(Uniform(rng, 0.0, 7.99));
        options.lambda = Uniform(rng, 0.0, 1.0);
        const auto hull = ComputeExtentHull(room.c.viewer, room.c.light, room.c.bounds);
        ASSERT_TRUE(hull.ok()) << hull.error().Message();
        const auto cascades = FitCascades(InputOf(room, budget), *hull, options);
        ASSERT_TRUE(cascades.ok()) << cascades.error().Message();
        const auto plan =
            PlanBaseline(RequestOf(room, budget), BaselineFitting::kCsm, *hull, options);
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        ASSERT_EQ(plan->maps.size(), cascades->cascades.size());
        EXPECT_LE(plan->total_lixels, budget);
        EXPECT_EQ(static_cast<int>(cascades->cascades.size()) + cascades->left_out, options.count);
        const int side = SquareSide(budget / options.count);
        for (const Cascade& c : cascades->cascades) {
            EXPECT_EQ(c.map.width, side);
            EXPECT_EQ(c.map.height, side);
            EXPECT_EQ(c.stabilized, room.c.light.w() == 0.0);
            (c.stabilized ? stabilized : tight) += 1;
        }
        const Mat4 inverse = room.c.viewer.inverse();
        for (int k = 0; k < 200; ++k) {
            // A pixel's ray down to the floor y = 0, kept where the floor is in view.
            const Vec4 ndc(Uniform(rng, -1.0, 1.0), Uniform(rng, -1.0, 1.0), 0.0, 1.0);
            const Vec4 on_near = inverse * ndc;
            const Vec3 from = room.c.eye;
            const Vec3 ray = on_near.head<3>() / on_near.w() - from;
            if (!(ray.y() < 0.0)) continue;
            const Vec3 x = from + ray * (-from.y() / ray.y());
            const Vec4 clip = room.c.viewer * Point(x);
            if (!(clip.z() >= 0.0 && clip.z() <= clip.w())) continue;  // beyond the far plane
            const FloorRoom& r = room;
            if (!(x.cwiseAbs().maxCoeff() <= r.receivers[0].max.x())) continue;  // off the floor
            const double depth = ViewDepth(room.c.viewer, x);
            const int chosen = LookupMap(*plan, Point(x));
            ASSERT_GE(chosen, 0) << "view depth " << depth;
            const Cascade& c = cascades->cascades[chosen];
            // The first cascade whose slice reaches the depth (relative rounding of the limit).
            const double slack = 1e-9 * cascades->splits.back();
            EXPECT_LE(depth, chosen + 1 < static_cast<int>(cascades->cascades.size())
                                 ? c.z_end + slack
                                 : std::numeric_limits<double>::infinity());
            if (chosen > 0) {
                EXPECT_GT(depth, cascades->cascades[chosen - 1].z_end - slack);
            }
            const Vec4 p = c.map.matrix * Point(x);
            ASSERT_GT(p.w(), 0.0);
            EXPECT_GE(p.x() / p.w(), -1e-6 * side);
            EXPECT_LE(p.x() / p.w(), side * (1.0 + 1e-6));
            EXPECT_GE(p.y() / p.w(), -1e-6 * side);
            EXPECT_LE(p.y() / p.w(), side * (1.0 + 1e-6));
            const double d = StoredDepthOf(c.map, Point(x));
            EXPECT_GE(d, -1e-9);
            EXPECT_LE(d, 1.0 + 1e-9);
            ++points;
        }
    }
    // Both fits were exercised, on many points.
    EXPECT_GT(stabilized, 100);
    EXPECT_GT(tight, 100);
    EXPECT_GT(points, 20000);
}

// A viewer 1.7 above a large floor, turning about the vertical and walking: the receivers'
// view depth range, and so the splits and the spheres' radii, stay put, and each stabilized
// cascade's x and y rows change only by whole lixels (the texel grid is fixed in the world).
// The tight fit (stabilize off) moves its grid by fractions of a lixel: the test can tell.
TEST(Cascades, StableCascadesKeepTheTexelGridFixedInTheWorld) {
    const double half = 2000.0;
    FloorRoom room;
    room.c.viewport = {800, 600};
    room.c.bounds = {Vec3(-half, 0.0, -half), Vec3(half, 10.0, half)};
    room.c.light = Direction(Vec3(0.3, 1.0, 0.5));
    room.receivers = {Aabb{Vec3(-half, 0.0, -half), Vec3(half, 0.0, half)}};
    for (const bool stabilize : {true, false}) {
        std::vector<CascadedMaps> frames;
        for (int f = 0; f < 24; ++f) {
            const double yaw = 0.013 * f;
            const Vec3 eye(0.37 * f, 1.7, -0.21 * f);
            const Vec3 forward(std::sin(yaw), -0.2, -std::cos(yaw));
            room.c.eye = eye;
            room.c.viewer = Perspective(60.0 * std::numbers::pi / 180.0, 800.0 / 600.0, 0.5, 200.0) *
                            LookAt(eye, eye + forward, Vec3::UnitY());
            const auto hull = ComputeExtentHull(room.c.viewer, room.c.light, room.c.bounds);
            ASSERT_TRUE(hull.ok()) << hull.error().Message();
            CascadeOptions options;
            options.stabilize = stabilize;
            auto fitted = FitCascades(InputOf(room, 1024 * 1024), *hull, options);
            ASSERT_TRUE(fitted.ok()) << fitted.error().Message();
            ASSERT_EQ(fitted->cascades.size(), 4u);
            frames.push_back(std::move(fitted.value()));
        }
        int fractional = 0;
        for (std::size_t f = 1; f < frames.size(); ++f) {
            for (std::size_t i = 0; i < 4; ++i) {
                const Cascade& a = frames[f - 1].cascades[i];
                const Cascade& b = frames[f].cascades[i];
                for (int row = 0; row < 2; ++row) {
                    const RowVec4 ra = a.map.matrix.row(row);
                    const RowVec4 rb = b.map.matrix.row(row);
                    const double shift = rb(3) - ra(3);  // lixels, for the same axes and scale
                    const bool same_axes =
                        (ra.head<3>() - rb.head<3>()).norm() <= 1e-12 * ra.head<3>().norm();
                    const bool whole = std::abs(shift - std::round(shift)) <= 1e-6;
                    if (stabilize) {
                        EXPECT_TRUE(same_axes) << "frame " << f << " cascade " << i;
                        EXPECT_TRUE(whole) << "frame " << f << " cascade " << i << ": " << shift;
                        EXPECT_EQ(a.sphere_radius, b.sphere_radius);
                    }
                    if (!same_axes || !whole) ++fractional;
                }
            }
        }
        std::printf("[ measured ] %s: %d of %zu row changes are not whole lixels\n",
                    stabilize ? "stabilized" : "tight", fractional, 8 * (frames.size() - 1));
        if (!stabilize) {
            EXPECT_GT(fractional, 100);
        }
    }
}

TEST(Cascades, BadInputIsRefusedNamingTheField) {
    std::mt19937_64 rng(3);
    const FloorRoom room = RandomFloorRoom(rng);
    const auto hull = ComputeExtentHull(room.c.viewer, room.c.light, room.c.bounds);
    ASSERT_TRUE(hull.ok());
    const BaselineInput input = InputOf(room, 512 * 512);
    struct Case {
        CascadeOptions options;
        std::int64_t budget;
        const char* field;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Case cases[] = {
        {{0, 0.5, true}, 512 * 512, "cascades.count"},
        {{9, 0.5, true}, 512 * 512, "cascades.count"},
        {{-1, 0.5, true}, 512 * 512, "cascades.count"},
        {{4, -0.01, true}, 512 * 512, "cascades.lambda"},
        {{4, 1.01, true}, 512 * 512, "cascades.lambda"},
        {{4, nan, true}, 512 * 512, "cascades.lambda"},
        {{4, 0.5, true}, 3, "lixel_budget"},
        {{4, 0.5, true}, 0, "lixel_budget"},
    };
    for (const Case& c : cases) {
        BaselineInput in = input;
        in.lixel_budget = c.budget;
        const auto fitted = FitCascades(in, *hull, c.options);
        ASSERT_FALSE(fitted.ok());
        EXPECT_EQ(fitted.error().field, c.field) << fitted.error().Message();
    }
    // A light inside H is refused as every baseline refuses it.
    const Vec4 inside = Point(0.5 * (room.c.eye + room.c.target));
    const auto inner = ComputeExtentHull(room.c.viewer, inside, room.c.bounds);
    ASSERT_TRUE(inner.ok());
    if (inner->light_inside) {
        BaselineInput in = input;
        in.light = inside;
        const auto fitted = FitCascades(in, *inner);
        ASSERT_FALSE(fitted.ok());
        EXPECT_EQ(fitted.error().field, "hull");
    }
}

TEST(Cascades, AnOrthographicViewerGetsOneCascadeOverEverything) {
    FloorRoom room;
    room.c.viewport = {512, 512};
    room.c.bounds = {Vec3(-10.0, 0.0, -10.0), Vec3(10.0, 3.0, 10.0)};
    room.c.light = Direction(Vec3(0.2, 1.0, 0.1));
    room.c.viewer = Orthographic(8.0, 8.0, 0.1, 100.0) *
                    LookAt(Vec3(0.0, 20.0, 5.0), Vec3::Zero(), Vec3::UnitY());
    room.receivers = {Aabb{Vec3(-10.0, 0.0, -10.0), Vec3(10.0, 0.0, 10.0)}};
    const auto hull = ComputeExtentHull(room.c.viewer, room.c.light, room.c.bounds);
    ASSERT_TRUE(hull.ok());
    const auto fitted = FitCascades(InputOf(room, 512 * 512), *hull);
    ASSERT_TRUE(fitted.ok()) << fitted.error().Message();
    ASSERT_EQ(fitted->cascades.size(), 1u);
    EXPECT_TRUE(fitted->cascades[0].view_limit.isZero());
    EXPECT_FALSE(fitted->note.empty());
    EXPECT_EQ(fitted->cascades[0].map.width, 512);
}

}  // namespace
}  // namespace lixel
