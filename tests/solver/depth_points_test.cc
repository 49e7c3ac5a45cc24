// Tests for the scheduler's depth points (solver/src/scheduler_depth_points.cc, an internal
// header's function): every region's points are those of plain clips of every box, and leaving
// out the held regions that cannot change a depth fit must leave the fitted depth row and a plane
// solve's reach bit for bit what every region gives.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/light_frustum.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "scheduler_context.h"
#include "test_scenes.h"

namespace lixel::scheduling {
namespace {

using testing::Uniform;

constexpr double kDegree = std::numbers::pi / 180.0;

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// The farthest of `points` and `receivers` from the point light `light` (w = 1), as
// ValidatePlaneOptimalInput takes its reach.
double Reach(const std::vector<Vec4>& points, const std::vector<Vec4>& receivers,
             const Vec4& light) {
    double reach = 0.0;
    for (const std::vector<Vec4>* set : {&points, &receivers}) {
        for (const Vec4& x : *set) {
            if (x.w() > 0.0)
                reach = std::max(reach, (x.head<3>() / x.w() - light.head<3>()).norm());
        }
    }
    return reach;
}

// Every object's part inside the extent hull and the map's accepted cone, clipped plane by plane
// with no shortcut (no object tree, no bounds), its vertices in object order: what DepthPoints
// takes every region of.
std::vector<Vec4> EveryRegionsPoints(const Context& c, const LightMap& map) {
    std::vector<PlaneTest> inside_hull;
    for (std::size_t f = 0; f < c.hull.hull.face_count(); ++f) {
        inside_hull.emplace_back(-c.hull.hull.face_plane(f));
    }
    const std::vector<PlaneTest> cone = PlaneTests(AcceptedCone(map, {}).planes);
    std::vector<Vec4> points;
    for (const SceneObject& o : c.request.objects) {
        const ConvexPolytope held =
            ClippedByAll(ConvexPolytope::FromBox(Thickened(o.bounds, c.thickness)), inside_hull);
        if (held.empty()) continue;
        for (const Vec3& v : ClippedByAll(held, cone).vertices()) points.push_back(Point(v));
    }
    return points;
}

// A room of seeded boxes under a point light (w other than 1 in some rooms): most stand on the
// floor, some float anywhere, and in some rooms a few crowd round the light (nearer than the
// near clamp, or holding it).
PlanRequest RandomRoom(std::mt19937_64& rng, int trial) {
    PlanRequest r;
    r.viewer = Perspective(Uniform(rng, 40, 90) * kDegree, 1.0, 0.1, 100.0) *
               LookAt(Vec3(Uniform(rng, -6, 6), Uniform(rng, 1, 6), Uniform(rng, 4, 9)),
                      Vec3(Uniform(rng, -3, 3), 0.5, Uniform(rng, -4, 0)), Vec3::UnitY());
    r.viewport = {512, 512};
    const Vec3 light(Uniform(rng, -8, 8), Uniform(rng, 3, 7.5), Uniform(rng, -4, 8));
    r.light = Point(light);
    if (trial % 3 == 1) r.light *= Uniform(rng, 0.01, 50.0);
    r.scene_bounds = Aabb{Vec3(-10, 0, -5), Vec3(10, 8, 10)};
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}}, {"wall", Vec4(0, 0, 1, 5), {}}};
    const int boxes = 40 + static_cast<int>(rng() % 260);
    for (int i = 0; i < boxes; ++i) {
        const double x = Uniform(rng, -9.5, 9.5), z = Uniform(rng, -4.5, 9.5);
        const double w = Uniform(rng, 0.05, 0.8), h = Uniform(rng, 0.05, 2.0);
        const double base = i % 4 == 3 ? Uniform(rng, 0.0, 7.9 - h) : 0.0;
        r.objects.push_back(testing::Box("box" + std::to_string(i), Vec3(x - w, base, z - w),
                                         Vec3(x + w, base + h, z + w)));
    }
    if (trial % 4 == 2) {
        for (int i = 0; i < 3; ++i) {
            const double s = i == 0 ? 0.2 : Uniform(rng, 1e-4, 1e-2);
            const Vec3 at = light + Vec3(Uniform(rng, -0.1, 0.1), Uniform(rng, -0.1, 0.1),
                                         Uniform(rng, -0.1, 0.1));
            r.objects.push_back(testing::Box("near" + std::to_string(i), at - Vec3::Constant(s),
                                             at + Vec3::Constant(s)));
        }
    }
    return r;
}

// Over rooms of 40 to 302 boxes and maps over a patch of the floor or over all of it: DepthPoints
// without a fit gives every box's plain clips' vertices, and FitDepthRow over the points
// DepthPoints keeps for a fit equals, bit for bit, the row over every region's points, and so does
// the reach; every point kept is one of the full set's.
TEST(DepthPoints, LeavingOutRegionsKeepsTheFittedRowAndReachBitForBit) {
    std::mt19937_64 rng(29029);
    int compared = 0, reduced = 0, clamped = 0;
    for (int trial = 0; trial < 150; ++trial) {
        const PlanRequest r = RandomRoom(rng, trial);
        const auto bounds = ValidatedBounds(r);
        ASSERT_TRUE(bounds.ok()) << bounds.error().Message();
        const auto hull = ComputeExtentHull(r.viewer, r.light, *bounds);
        if (!hull) continue;
        const Context c = MakeContext(r, *bounds, *hull);
        const Vec4 light = hull->light;  // w = 1
        // Receivers: seeded points of the floor under the view's middle, or of the whole room.
        std::vector<Vec4> receivers;
        const double reach = trial % 5 == 0 ? 9.0 : Uniform(rng, 0.5, 4.0);
        const Vec3 centre(Uniform(rng, -5, 5), 0.0, Uniform(rng, -3, 6));
        for (int k = 0; k < 12; ++k) {
            receivers.push_back(Point(
                centre + Vec3(Uniform(rng, -reach, reach), 0.0, Uniform(rng, -reach, reach))));
        }
        // A map over the receivers alone, or over the whole floor of the room.
        std::vector<Vec4> held = receivers;
        if (trial % 2 == 1) {
            held = {Point(Vec3(-10, 0, -5)), Point(Vec3(10, 0, -5)), Point(Vec3(10, 0, 10)),
                    Point(Vec3(-10, 0, 10))};
        }
        const auto map = FitFrustum(light, held, MapSize{0, 0, 256 * 256});
        if (!map) continue;
        const DepthFit fit{map->matrix.row(3), light, receivers, true};
        const std::vector<Vec4> full = EveryRegionsPoints(c, *map);
        ASSERT_EQ(DepthPoints(c, *map, {}), full) << "trial " << trial;
        const std::vector<Vec4> kept = DepthPoints(c, *map, {}, &fit);
        ASSERT_LE(kept.size(), full.size());
        for (const Vec4& x : kept) {
            ASSERT_TRUE(std::find(full.begin(), full.end(), x) != full.end()) << "trial " << trial;
        }
        const auto row_full = FitDepthRow(fit.r_w, light, full, receivers);
        const auto row_kept = FitDepthRow(fit.r_w, light, kept, receivers);
        ASSERT_EQ(row_full.ok(), row_kept.ok()) << "trial " << trial;
        if (row_full.ok()) {
            for (int k = 0; k < 4; ++k) {
                EXPECT_TRUE(SameBits((*row_full)(k), (*row_kept)(k)))
                    << "trial " << trial << " entry " << k << ": " << (*row_full)(k) << " against "
                    << (*row_kept)(k);
            }
        } else {
            EXPECT_EQ(row_full.error().Message(), row_kept.error().Message());
        }
        EXPECT_TRUE(SameBits(Reach(full, receivers, light), Reach(kept, receivers, light)))
            << "trial " << trial;
        // Whether some point lies below the near clamp (FitDepthRow's floor).
        double q_max = 0.0, q_min = std::numeric_limits<double>::infinity();
        for (const Vec4& x : receivers) {
            q_max = std::max(q_max, fit.r_w.dot(x));
            q_min = std::min(q_min, fit.r_w.dot(x));
        }
        for (const Vec4& x : full) q_max = std::max(q_max, fit.r_w.dot(x));
        const double floor = std::min(q_max * kMinNearRatio, q_min);
        clamped += std::any_of(full.begin(), full.end(),
                               [&](const Vec4& x) { return !(fit.r_w.dot(x) >= floor); });
        reduced += kept.size() * 2 < full.size();
        ++compared;
    }
    EXPECT_GT(compared, 120);
    EXPECT_GT(reduced, 60);  // most fits leave out more than half the points
    EXPECT_GT(clamped, 10);  // and some hold points below the near clamp
    RecordProperty("reduced", std::to_string(reduced));
    RecordProperty("clamped", std::to_string(clamped));
}

}  // namespace
}  // namespace lixel::scheduling
