// Tests for map_diagnostics.h's receivers: the fallback's figures come from samples of its
// region's faces, every face while they are few, an evenly strided share of the faces once they
// pass kMaxRegionReceivers, so a plan over thousands of objects measures a bounded sample.
#include <gtest/gtest.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/scheduler.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Uniform;

// `count` boxes around the origin, one in three cut by a random plane through it so faces
// differ in size (triangles to heptagons).
std::vector<ConvexPolytope> RandomRegions(std::mt19937_64& rng, int count) {
    std::vector<ConvexPolytope> out;
    while (static_cast<int>(out.size()) < count) {
        const Vec3 c(Uniform(rng, -10, 10), Uniform(rng, -10, 10), Uniform(rng, -10, 10));
        const Vec3 half(Uniform(rng, 0.1, 2), Uniform(rng, 0.1, 2), Uniform(rng, 0.1, 2));
        ConvexPolytope box = ConvexPolytope::FromBox(Aabb{c - half, c + half});
        if (std::uniform_int_distribution<int>(0, 2)(rng) == 0) {
            const Vec3 n = testing::RandomUnit(rng);
            box.Clip(Vec4(n.x(), n.y(), n.z(), -n.dot(c) + 0.3 * half.minCoeff()));
        }
        if (!box.empty()) out.push_back(std::move(box));
    }
    return out;
}

bool SameReceiver(const Receiver& a, const Receiver& b) {
    return (a.point.array() == b.point.array()).all() && (a.plane.array() == b.plane.array()).all();
}

// Below the bound every face is sampled, bit for bit as with no bound; above it, the samples of
// every k-th face in order (the first face always), at most the bound and at least a quarter of
// it, drawn from across the whole list of regions.
TEST(RegionReceivers, EveryFaceBelowTheBoundAnEvenStrideOfFacesAboveIt) {
    std::mt19937_64 rng(5120);
    constexpr std::size_t kBound = kMaxRegionReceivers;
    for (int count : {1, 3, 10, 15, 16, 40, 200, 1000, 3000}) {
        SCOPED_TRACE(std::to_string(count) + " regions");
        const std::vector<ConvexPolytope> regions = RandomRegions(rng, count);
        // Every face's samples, taken here from the faces themselves.
        std::vector<Receiver> all;
        for (const ConvexPolytope& region : regions) {
            for (const PolytopeFace& f : region.faces()) {
                for (const Vec3& p : SamplePolygon(f.polygon)) all.push_back({p, f.outward_plane});
            }
        }
        const std::vector<Receiver> unbounded = RegionReceivers(regions, 0);
        ASSERT_EQ(unbounded.size(), all.size());
        for (std::size_t i = 0; i < all.size(); ++i) {
            EXPECT_TRUE(SameReceiver(unbounded[i], all[i])) << i;
        }
        const std::vector<Receiver> bounded = RegionReceivers(regions);
        if (all.size() <= kBound) {
            ASSERT_EQ(bounded.size(), all.size());
            for (std::size_t i = 0; i < all.size(); ++i) {
                EXPECT_TRUE(SameReceiver(bounded[i], all[i])) << i;
            }
            continue;
        }
        EXPECT_LE(bounded.size(), kBound);
        EXPECT_GE(bounded.size(), kBound / 4);
        // Each face's samples, in order, with the index of the face and its region.
        struct Face {
            std::size_t first, count, region;
        };
        std::vector<Face> faces;
        std::size_t at = 0;
        for (std::size_t r = 0; r < regions.size(); ++r) {
            for (const PolytopeFace& f : regions[r].faces()) {
                const std::size_t n = SamplePolygon(f.polygon).size();
                faces.push_back({at, n, r});
                at += n;
            }
        }
        ASSERT_EQ(at, all.size());
        // The stride is the distance to the second kept face; every kept sample is then that
        // face's, in order.
        ASSERT_GT(bounded.size(), faces[0].count);
        std::size_t stride = 1;
        while (stride < faces.size() &&
               !SameReceiver(all[faces[stride].first], bounded[faces[0].count])) {
            ++stride;
        }
        ASSERT_LT(stride, faces.size());
        std::size_t k = 0;
        std::size_t last_region = 0;
        for (std::size_t f = 0; f < faces.size(); f += stride) {
            for (std::size_t s = 0; s < faces[f].count; ++s, ++k) {
                ASSERT_LT(k, bounded.size());
                EXPECT_TRUE(SameReceiver(bounded[k], all[faces[f].first + s]));
            }
            last_region = faces[f].region;
        }
        EXPECT_EQ(k, bounded.size());
        // Spread: the last kept face lies in the list's last stride of faces.
        EXPECT_GE(last_region, faces[faces.size() - stride].region);
    }
}

// A room with 1 000 boxes standing on the floor: the fallback's figures come from at most
// kMaxRegionReceivers samples of its region, and are still figures. Without the bound every
// sample was measured (10 326 held here), which cost a quarter of a 10 000-object plan.
TEST(RegionReceivers, ALargeScenesFallbackIsMeasuredOnABoundedSample) {
    PlanRequest r = testing::FloorWallRoomRequest(1024 * 1024);
    std::mt19937_64 rng(29);
    while (r.objects.size() < 1000) {
        const double x = Uniform(rng, -9.5, 9.5), z = Uniform(rng, -4.5, 9.5);
        const double w = Uniform(rng, 0.05, 1.0), h = Uniform(rng, 0.05, 1.0);
        r.objects.push_back(testing::Box("box" + std::to_string(r.objects.size()),
                                         Vec3(x - w / 2, 0, z - w / 2),
                                         Vec3(x + w / 2, h, z + w / 2)));
    }
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    const PlannedMap* fallback = nullptr;
    for (const PlannedMap& m : plan->maps) {
        if (m.role != MapRole::kPlane) fallback = &m;
    }
    ASSERT_NE(fallback, nullptr);
    const SolveDiagnostics& d = fallback->diagnostics;
    EXPECT_GT(d.samples, 0);
    EXPECT_LE(d.samples, static_cast<int>(kMaxRegionReceivers));
    EXPECT_GT(d.lixels_per_pixel_min, 0.0);
    EXPECT_LE(d.lixels_per_pixel_min, d.lixels_per_pixel_max);
    EXPECT_GT(d.depth_resolution, 0.0);
}

// DiagnoseMap with a flag a receiver gives, bit for bit, what it gives the flagged receivers
// alone (the fallback's figures flag the receivers its lookup holds, where it copied them), the
// first flagged one still its GL origin: seeded random views, frustum maps fitted around them,
// receivers on the faces of boxes there, one in three to all flagged.
TEST(DiagnoseMap, FlaggedReceiversGiveTheFiguresOfThoseReceiversAlone) {
    std::mt19937_64 rng(2904);
    int compared = 0;
    for (int i = 0; i < 300; ++i) {
        const testing::Configuration c = testing::RandomConfiguration(rng);
        const double reach = (c.target - c.eye).norm();
        std::vector<Vec4> corners;
        std::vector<ConvexPolytope> boxes;
        for (int k = 0; k < 3; ++k) {
            const Vec3 centre =
                c.target + reach * Vec3(Uniform(rng, -0.5, 0.5), Uniform(rng, -0.5, 0.5),
                                        Uniform(rng, -0.5, 0.5));
            const Vec3 half = reach * Vec3(Uniform(rng, 0.05, 0.3), Uniform(rng, 0.05, 0.3),
                                           Uniform(rng, 0.05, 0.3));
            boxes.push_back(ConvexPolytope::FromBox(Aabb{centre - half, centre + half}));
            for (const Vec3& v : boxes.back().vertices()) corners.push_back(Point(v));
        }
        const auto map = FitFrustum(c.light, corners, MapSize{0, 0, 256 * 256});
        if (!map) continue;
        const std::vector<Receiver> receivers = RegionReceivers(boxes);
        const double share = Uniform(rng, 0.3, 1.0);
        std::vector<std::uint8_t> held(receivers.size());
        std::vector<Receiver> alone;
        for (std::size_t k = 0; k < receivers.size(); ++k) {
            held[k] = std::bernoulli_distribution(share)(rng) ? 1 : 0;
            if (held[k] != 0) alone.push_back(receivers[k]);
        }
        const SolveDiagnostics flagged =
            DiagnoseMap(*map, c.light, c.viewer, c.viewport, receivers, held);
        const SolveDiagnostics subset = DiagnoseMap(*map, c.light, c.viewer, c.viewport, alone);
        EXPECT_EQ(flagged.samples, subset.samples) << "view " << i;
        for (const auto field :
             {&SolveDiagnostics::lixels_per_pixel_min, &SolveDiagnostics::lixels_per_pixel_max,
              &SolveDiagnostics::depth_resolution, &SolveDiagnostics::depth_step_nearest,
              &SolveDiagnostics::depth_step_farthest}) {
            EXPECT_EQ(std::memcmp(&(flagged.*field), &(subset.*field), sizeof(double)), 0)
                << "view " << i << ": " << flagged.*field << " against " << subset.*field;
        }
        compared += subset.samples > 0 ? 1 : 0;
    }
    EXPECT_GT(compared, 150);
}

// DepthStepAt as first written: the light's point or direction taken at every receiver, the
// distance along the light apart.
double PlainDepthStep(const LightMap& map, const GlLightTransform& gl, const Vec4& light,
                      const Vec3& x) {
    const bool directional = light.w() == 0.0;
    const Vec3 dir3 = directional ? Vec3(-light.head<3>().normalized())
                                  : Vec3((x - light.head<3>() / light.w()).normalized());
    const Vec4 dir(dir3.x(), dir3.y(), dir3.z(), 0.0);
    const Vec4 p = Point(x);
    const RowVec4 r_z = map.matrix.row(2);
    const RowVec4 r_w = map.matrix.row(3);
    const double q = r_w.dot(p);
    const double dz = (r_z.dot(dir) * q - r_z.dot(p) * r_w.dot(dir)) / (q * q);
    if (!(dz != 0.0) || !std::isfinite(dz)) return 0.0;
    const Eigen::Vector3f local = (x - gl.origin).cast<float>();
    const Eigen::Vector4f local4(local.x(), local.y(), local.z(), 1.0f);
    const Eigen::Vector4f row = gl.projection.row(2).transpose();
    const float w = gl.projection.row(3).dot(local4.transpose());
    const float d = std::clamp(row.dot(local4) / w, 0.0f, 1.0f);
    const double storage = static_cast<double>(std::nextafter(d, 2.0f)) - static_cast<double>(d);
    const double terms = row.cwiseProduct(local4).cwiseAbs().cast<double>().sum();
    const double computed = 0.5 * std::numeric_limits<float>::epsilon() * terms / std::abs(w);
    return std::max(storage, computed) / std::abs(dz);
}

// The light taken once (DepthStepLight) gives every receiver the step and the distance along the
// light the plain computation gives, bit for bit: point lights with w other than 1, directional
// lights, receivers at the light and at depths the pass clamps to 0 or 1.
TEST(DepthStepAt, TheLightTakenOnceGivesThePlainStepsAndDistancesBitForBit) {
    std::mt19937_64 rng(2941);
    int compared = 0;
    for (int i = 0; i < 300; ++i) {
        const testing::Configuration c = testing::RandomConfiguration(rng);
        const double reach = (c.target - c.eye).norm();
        std::vector<Vec4> corners;
        for (int k = 0; k < 8; ++k) {
            corners.push_back(
                Point(Vec3(c.target + reach * Vec3(Uniform(rng, -0.5, 0.5), Uniform(rng, -0.5, 0.5),
                                                   Uniform(rng, -0.5, 0.5)))));
        }
        Vec4 light = c.light;
        if (i % 3 == 1 && light.w() != 0.0) light *= Uniform(rng, 0.01, 100.0);  // w not 1
        const auto map = FitFrustum(light, corners, MapSize{0, 0, 256 * 256});
        if (!map) continue;
        const GlLightTransform gl = ToGl(*map, corners[0].head<3>());
        const DepthStepLight once(light);
        for (int k = 0; k < 20; ++k) {
            Vec3 x = c.target + reach * Vec3(Uniform(rng, -0.5, 0.5), Uniform(rng, -0.5, 0.5),
                                             Uniform(rng, -0.5, 0.5));
            if (k == 0 && light.w() != 0.0) x = light.head<3>() / light.w();  // at the light
            // Depths the pass clamps: far past the corners (1), and between the light and its
            // near plane or behind a directional light's (0).
            const Vec3 toward = light.w() == 0.0
                                    ? Vec3(-light.head<3>().normalized())
                                    : Vec3((c.target - light.head<3>() / light.w()).normalized());
            if (k == 1) x = c.target + 50.0 * reach * toward;
            if (k == 2 && light.w() != 0.0) x = light.head<3>() / light.w() + 1e-3 * reach * toward;
            if (k == 2 && light.w() == 0.0) x = c.target - 50.0 * reach * toward;
            const DepthStep got = DepthStepAt(*map, gl, once, x);
            const double step = PlainDepthStep(*map, gl, light, x);
            const double along = light.w() == 0.0 ? -light.head<3>().normalized().dot(x)
                                                  : (x - light.head<3>() / light.w()).norm();
            EXPECT_EQ(std::memcmp(&got.step, &step, sizeof(double)), 0)
                << "view " << i << ": " << got.step << " against " << step;
            EXPECT_EQ(std::memcmp(&got.along, &along, sizeof(double)), 0)
                << "view " << i << ": " << got.along << " against " << along;
            const double legacy = DepthStepAt(*map, gl, light, x);
            EXPECT_EQ(std::memcmp(&legacy, &step, sizeof(double)), 0) << "view " << i;
            ++compared;
        }
    }
    EXPECT_GT(compared, 3000);
}

}  // namespace
}  // namespace lixel
