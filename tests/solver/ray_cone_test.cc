// Tests for ray_cone.h's proof that a region needs no subtraction (SubtractAllLeavesNothing):
// wherever it holds, SubtractAll leaves nothing, over seeded regions at every scale and cones
// through a light whose planes pass the regions by little or touch their corners.
#include <gtest/gtest.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/ray_cone.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

// A plane through `light` with normal n, oriented so that `inside` is on its side.
Vec4 PlaneThrough(const Vec3& light, const Vec3& n, const Vec3& inside) {
    const Vec4 plane(n.x(), n.y(), n.z(), -n.dot(light));
    return plane.dot(Point(inside)) >= 0.0 ? plane : Vec4(-plane);
}

TEST(RayCone, SubtractAllLeavesNothingWhereItSaysSo) {
    std::mt19937_64 rng(2931);
    int proved = 0, proved_past_a_cutting_cone = 0, refused = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const double scale = std::pow(10.0, -3.0 + 8.0 * (trial % 9) / 8.0);
        const Vec3 centre =
            4.0 * scale * Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
        const Vec3 half =
            0.5 * scale * Vec3(Uniform(rng, 0.05, 1), Uniform(rng, 0.05, 1), Uniform(rng, 0.05, 1));
        // A view region: the box, cut by up to three planes through points inside it.
        ConvexPolytope region = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        for (int k = 0; k < trial % 4; ++k) {
            const Vec3 n = RandomUnit(rng);
            const Vec3 through =
                centre + half.cwiseProduct(Vec3(Uniform(rng, -0.8, 0.8), Uniform(rng, -0.8, 0.8),
                                                Uniform(rng, -0.8, 0.8)));
            region.Clip(Vec4(n.x(), n.y(), n.z(), -n.dot(through)));
        }
        if (region.empty()) continue;
        const PolytopeBounds bounds = region.Bounds();
        const Vec3 middle = 0.5 * (bounds.lo + bounds.hi);
        const std::vector<Vec3> corners = region.vertices();
        // The light from 1.5 to 30 region sizes away: near, many planes cut the region.
        const Vec3 light = middle + scale * Uniform(rng, 1.5, 30.0) * RandomUnit(rng);
        std::vector<RayConeTests> cones;
        const int cone_count = 1 + trial % 3;
        for (int c = 0; c < cone_count; ++c) {
            RayCone cone;
            for (int p = 0; p < 4 + (trial + c) % 4; ++p) {
                Vec3 n = RandomUnit(rng);
                if ((trial + c) % 3 == 0 && p == 2) {
                    // Through the light and a vertex of the region: it touches the region there.
                    const Vec3 towards = corners[rng() % corners.size()] - light;
                    n = towards.cross(RandomUnit(rng)).normalized();
                }
                cone.planes.push_back(PlaneThrough(light, n, middle));
            }
            cones.emplace_back(cone);
        }
        if (!SubtractAllLeavesNothing(bounds, cones)) {
            ++refused;
            continue;
        }
        ++proved;
        EXPECT_TRUE(SubtractAll(region, std::span<const RayConeTests>(cones)).empty())
            << "trial " << trial;
        // Proved by a later cone where the first one cuts the region into pieces.
        if (!Subtract(region, cones.front()).empty()) ++proved_past_a_cutting_cone;
    }
    EXPECT_GT(proved, 400);
    EXPECT_GT(proved_past_a_cutting_cone, 50);
    EXPECT_GT(refused, 400);
}

// Past the clips its margin covers, the proof is not offered: 41 and more planes of the cones
// before can cut the parts that reach a cone.
TEST(RayCone, SubtractAllLeavesNothingOnlyWithinTheClipsItsMarginCovers) {
    const ConvexPolytope region = ConvexPolytope::FromBox(Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    const Vec3 light(0, 0, 50);
    // A cone holding the region, and 41 planes of one that cuts it in half before it.
    RayCone holding, halving;
    for (const Vec3& n : {Vec3(1, 0, 0.1), Vec3(-1, 0, 0.1), Vec3(0, 1, 0.1), Vec3(0, -1, 0.1)}) {
        holding.planes.push_back(PlaneThrough(light, n.normalized(), Vec3::Zero()));
    }
    for (int k = 0; k < 41; ++k) {
        halving.planes.push_back(PlaneThrough(light, Vec3(1, 0, 0), Vec3(10, 0, 0)));
    }
    std::vector<RayConeTests> cones = {RayConeTests(holding)};
    EXPECT_TRUE(SubtractAllLeavesNothing(region.Bounds(), cones));
    cones.insert(cones.begin(), RayConeTests(halving));
    EXPECT_FALSE(SubtractAllLeavesNothing(region.Bounds(), cones));
    halving.planes.pop_back();
    cones.front() = RayConeTests(halving);
    EXPECT_TRUE(SubtractAllLeavesNothing(region.Bounds(), cones));
}

// Subtract as written plainly: a copy of the region clipped plane after plane, each piece a copy
// clipped by one negated plane. Subtract and SubtractAll take pieces left whole on without
// copies; their pieces must be these, bit for bit and in order.
std::vector<ConvexPolytope> PlainSubtract(const ConvexPolytope& region, const RayCone& cone) {
    std::vector<ConvexPolytope> pieces;
    ConvexPolytope inside = region;
    for (const Vec4& plane : cone.planes) {
        if (inside.empty()) break;
        ConvexPolytope outside = inside;
        outside.Clip(Vec4(-plane));
        if (!outside.empty()) pieces.push_back(outside);
        inside.Clip(plane);
    }
    return pieces;
}

void ExpectSamePieces(const std::vector<ConvexPolytope>& got,
                      const std::vector<ConvexPolytope>& expected, int trial) {
    ASSERT_EQ(got.size(), expected.size()) << "trial " << trial;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const std::vector<PolytopeFace> a = got[i].faces(), b = expected[i].faces();
        ASSERT_EQ(a.size(), b.size()) << "trial " << trial << " piece " << i;
        for (std::size_t f = 0; f < a.size(); ++f) {
            ASSERT_EQ(a[f].polygon.size(), b[f].polygon.size());
            for (std::size_t k = 0; k < a[f].polygon.size(); ++k) {
                for (int c = 0; c < 3; ++c) {
                    ASSERT_EQ(a[f].polygon[k](c), b[f].polygon[k](c)) << "trial " << trial;
                }
            }
            for (int c = 0; c < 4; ++c) ASSERT_EQ(a[f].outward_plane(c), b[f].outward_plane(c));
        }
    }
}

TEST(RayCone, SubtractGivesThePiecesOfThePlainSubtractionBitForBit) {
    std::mt19937_64 rng(2937);
    int whole = 0, cut = 0, gone = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const double scale = std::pow(10.0, -3.0 + 6.0 * (trial % 7) / 6.0);
        const Vec3 centre =
            scale * Vec3(Uniform(rng, -3, 3), Uniform(rng, -3, 3), Uniform(rng, -3, 3));
        const Vec3 half =
            scale * Vec3(Uniform(rng, 0.05, 1), Uniform(rng, 0.05, 1), Uniform(rng, 0.05, 1));
        const ConvexPolytope region = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        const Vec3 light = centre + scale * Uniform(rng, 2.0, 20.0) * RandomUnit(rng);
        std::vector<RayCone> cones(1 + trial % 4);
        std::vector<RayConeTests> tests;
        for (RayCone& cone : cones) {
            // Planes through the light, each toward a point near the region: some hold it whole,
            // some pass through it, some leave it wholly outside.
            const long kind = (trial + (&cone - cones.data())) % 3;
            for (int p = 0; p < 3 + static_cast<int>(rng() % 4); ++p) {
                if (kind != 0) {
                    // Random planes through the light with the region's centre inside, most of
                    // them holding the whole region; the first one turned away from it.
                    const Vec4 plane = PlaneThrough(light, RandomUnit(rng), centre);
                    cone.planes.push_back(kind == 2 && p == 0 ? Vec4(-plane) : plane);
                    continue;
                }
                const Vec3 toward =
                    centre + 1.5 * half.cwiseProduct(Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1),
                                                          Uniform(rng, -1, 1)));
                const Vec3 n = (toward - light).cross(RandomUnit(rng)).normalized();
                cone.planes.push_back(PlaneThrough(light, n, toward + scale * RandomUnit(rng)));
            }
            tests.emplace_back(cone);
        }
        const std::vector<ConvexPolytope> one = Subtract(region, tests.front());
        ExpectSamePieces(one, PlainSubtract(region, cones.front()), trial);
        whole += one.size() == 1 && one.front().Size() == region.Size();
        cut += one.size() > 1;
        // SubtractAll: the plain subtraction cone after cone.
        std::vector<ConvexPolytope> remaining = {region};
        for (const RayCone& cone : cones) {
            std::vector<ConvexPolytope> next;
            for (const ConvexPolytope& piece : remaining) {
                for (ConvexPolytope& rest : PlainSubtract(piece, cone)) next.push_back(rest);
            }
            remaining = std::move(next);
        }
        gone += remaining.empty();
        ExpectSamePieces(SubtractAll(region, std::span<const RayConeTests>(tests)), remaining,
                         trial);
    }
    EXPECT_GT(whole, 200);
    EXPECT_GT(cut, 200);
    EXPECT_GT(gone, 100);
}

}  // namespace
}  // namespace lixel
