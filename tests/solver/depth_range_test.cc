// Tests for depth_row.h through scheduler.h: every receiver a lookup sends to a map reads a
// depth inside [kClipDepthNear, kClipDepthFar], whatever the scene's scale, bounds or light.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/scheduler.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

namespace lixel {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
// Depth is computed in double from the map's matrix; the fit widens the range by 1e-6 of its
// span, so a receiver needs no tolerance beyond rounding of the product: 4 ulps of 1.
constexpr double kDepthSlack = 4.0 * std::numeric_limits<double>::epsilon();

struct Outcome {
    int sampled = 0;     // visible floor points looked up
    int held = 0;        // that some map accepts
    int outside = 0;     // whose depth lies outside [0, 1]
    double worst = 0.0;  // how far outside, in depth units
};

// A viewer above a ground plane y = 0 (a slab object, as the built-in scenes give it), a few
// boxes standing on it, a light; `scale` multiplies every length and `half` is the slab's half
// extent before scaling.
PlanRequest GroundRequest(double scale, double half, const Vec4& light, double eye_height,
                          double pitch_degrees) {
    PlanRequest r;
    const Vec3 eye(0.0, eye_height * scale, 0.0);
    const Vec3 ahead(0.0, -std::tan(pitch_degrees * kDegree), -1.0);
    r.viewer = Perspective(60.0 * kDegree, 1.0, 0.05 * scale, 1e3 * half * scale) *
               LookAt(eye, eye + ahead, Vec3::UnitY());
    r.viewport = {256, 256};
    r.light = light;
    SceneObject floor;
    floor.name = "ground";
    floor.bounds = {Vec3(-half, -0.1, -half) * scale, Vec3(half, 0.0, half) * scale};
    SceneObject box;
    box.name = "box";
    box.bounds = {Vec3(-1.0, 0.0, -4.0) * scale, Vec3(0.5, 1.0, -3.0) * scale};
    r.objects = {floor, box};
    r.planes = {{"ground", Vec4(0, 1, 0, 0), {}}};
    r.lixel_budget = 512 * 512;
    return r;
}

// Floor points under `samples` random viewer pixels, each looked up in the plan.
Outcome CheckReceivers(const PlanRequest& r, const Plan& plan, std::mt19937& rng, int samples) {
    Outcome o;
    const Mat4 unproject = PixelMatrix(r.viewer, r.viewport).inverse();
    std::uniform_real_distribution<double> px(0.0, r.viewport.width);
    std::uniform_real_distribution<double> py(0.0, r.viewport.height);
    const Aabb& ground = r.objects[0].bounds;
    for (int i = 0; i < samples; ++i) {
        const double x = px(rng);
        const double y = py(rng);
        const Vec4 a = unproject * Vec4(x, y, 0.0, 1.0);
        const Vec4 b = unproject * Vec4(x, y, 1.0, 1.0);
        const Vec3 o3 = a.head<3>() / a.w();
        const Vec3 d = b.head<3>() / b.w() - o3;
        if (!(d.y() < 0.0) || !(o3.y() > 0.0)) continue;
        const double t = -o3.y() / d.y();
        if (t > 1.0) continue;  // beyond the far plane
        Vec3 p = o3 + t * d;
        p.y() = 0.0;
        if (std::abs(p.x()) > ground.max.x() || std::abs(p.z()) > ground.max.z()) continue;
        ++o.sampled;
        const int k = LookupMap(plan, Point(p));
        if (k < 0) continue;
        ++o.held;
        const Vec4 h = plan.maps[k].map.matrix * Point(p);
        const double depth = h.z() / h.w();
        const double past = std::max(-depth, depth - 1.0);
        if (!(past <= kDepthSlack)) {
            ++o.outside;
            o.worst = std::max(o.worst, std::isfinite(past) ? past : 1e300);
        }
    }
    return o;
}

TEST(DepthRange, ALightSixMetresOverALargeGroundKeepsTheNearReceiversInRange) {
    // A 6 m point light over a ground plane of 1e5 bounds: the far corners set q_max, and the
    // near-ratio clamp alone would put the ground three metres ahead at depth -2.2.
    const PlanRequest r = GroundRequest(1.0, 1e5, Point(Vec3(2.0, 6.0, -3.0)), 1.7, 20.0);
    auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    std::mt19937 rng(6);
    const Outcome o = CheckReceivers(r, *plan, rng, 4000);
    std::printf("[ measured ] 6 m light, 1e5 bounds: %d of %d held floor points outside [0, 1], "
                "worst by %.3g\n",
                o.outside, o.held, o.worst);
    EXPECT_GT(o.held, 1000);
    EXPECT_EQ(o.outside, 0) << "worst by " << o.worst;
}

TEST(DepthRange, EveryHeldReceiverIsInsideTheDepthRangeOverRandomScalesAndLights) {
    std::mt19937 rng(1402);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int configurations = 0;
    int held = 0;
    int outside = 0;
    double worst = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const double scale = std::pow(10.0, -6.0 + 12.0 * unit(rng));
        const double half = std::pow(10.0, 1.0 + 4.0 * unit(rng));  // bounds up to 1e5
        const double pitch = 5.0 + 80.0 * unit(rng);
        Vec4 light;
        if (unit(rng) < 0.25) {
            const double elevation = (2.0 + 85.0 * unit(rng)) * kDegree;
            const double azimuth = 2.0 * std::numbers::pi * unit(rng);
            light = Vec4(std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                         std::cos(elevation) * std::sin(azimuth), 0.0);
        } else {
            // From a hand's breadth to far above, anywhere over the ground near the view.
            const double height = std::pow(10.0, -1.0 + 4.0 * unit(rng));
            light = Point(Vec3((unit(rng) - 0.5) * 40.0, height, -20.0 * unit(rng)) * scale);
        }
        const PlanRequest r = GroundRequest(scale, half, light, 0.5 + 3.0 * unit(rng), pitch);
        auto plan = PlanShadowMaps(r);
        if (!plan.ok()) continue;  // refused with a reason: not what this test is about
        ++configurations;
        const Outcome o = CheckReceivers(r, *plan, rng, 200);
        held += o.held;
        outside += o.outside;
        worst = std::max(worst, o.worst);
        if (o.outside > 0 && outside == o.outside) {
            ADD_FAILURE() << "configuration " << i << ": scale " << scale << ", bounds " << half
                          << ", pitch " << pitch << ", light " << light.transpose() << ": "
                          << o.outside << " of " << o.held << " outside by " << o.worst;
        }
    }
    std::printf("[ measured ] %d configurations, %d held floor points, %d outside [0, 1] "
                "(worst by %.3g)\n",
                configurations, held, outside, worst);
    EXPECT_GT(configurations, 1500);
    EXPECT_GT(held, 100000);
    EXPECT_EQ(outside, 0);
}

TEST(FitDepthRow, ReceiversAreNeverClampedAndOneAtInfinityPullsTheFarEndOut) {
    // A point light at the origin looking down -z (r_w = -z): casters from q = 1e-6 to 1e4, a
    // receiver at q = 1e-5, nearer than the ratio clamp (1e-4 * 1e4 = 1).
    const RowVec4 r_w(0.0, 0.0, -1.0, 0.0);
    const Vec4 light(0.0, 0.0, 0.0, 1.0);
    const std::vector<Vec4> casters = {Point(Vec3(0, 0, -1e-6)), Point(Vec3(0, 0, -1e4))};
    const std::vector<Vec4> receivers = {Point(Vec3(0.0, 0.0, -1e-5)),
                                         Vec4(0.0, 0.2, -1.0, 0.0)};  // at infinity
    auto clamped = FitDepthRow(r_w, light, casters);
    ASSERT_TRUE(clamped.ok()) << clamped.error().Message();
    auto fitted = FitDepthRow(r_w, light, casters, receivers);
    ASSERT_TRUE(fitted.ok()) << fitted.error().Message();
    auto depth = [](const RowVec4& r_z, const RowVec4& w, const Vec4& x) {
        return r_z.dot(x) / w.dot(x);
    };
    EXPECT_LT(depth(*clamped, r_w, receivers[0]), 0.0) << "the clamp alone cuts the receiver off";
    const double near = depth(*fitted, r_w, receivers[0]);
    const double far = depth(*fitted, r_w, receivers[1]);
    EXPECT_GE(near, 0.0);
    EXPECT_LE(near, 1e-5);
    EXPECT_LE(far, 1.0);
    EXPECT_GE(far, 1.0 - 1e-5);
    EXPECT_LT(depth(*fitted, r_w, casters[0]), 0.0) << "a caster nearer still is clamped";
    const std::vector<Vec4> behind = {Point(Vec3(0, 0, 1))};
    auto refused = FitDepthRow(r_w, light, casters, behind);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "receivers");
}

}  // namespace
}  // namespace lixel
