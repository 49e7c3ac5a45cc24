// Tests for the scheduler's object tree (solver/src/object_tree.h, an internal header): which
// boxes a set of clip planes may keep part of, found in groups, must be what testing every box
// alone finds, and the tree stays shallow whatever the boxes' layout.
#include "object_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel::scheduling {
namespace {

using testing::Uniform;

// The scan the tree must reproduce: a box is possible when no plane's group test rejects it.
std::vector<char> EveryBoxAlone(const std::vector<PolytopeBounds>& boxes,
                                const std::vector<PlaneTest>& planes) {
    std::vector<char> possible;
    for (const PolytopeBounds& b : boxes) {
        bool kept = !b.empty();
        for (const PlaneTest& p : planes) kept = kept && !b.KeepsNothingOf(p);
        possible.push_back(kept);
    }
    return possible;
}

// Seeded scenes of clustered boxes at every scale (empty ones among them), against sets of up to
// 70 planes (past the 64 the tree masks), planes through the scene, near its clusters, at
// infinity and not finite.
TEST(ObjectTree, MarksExactlyTheBoxesNoPlaneRejectsOverSeededScenes) {
    std::mt19937_64 rng(2977);
    int rejected = 0, kept = 0;
    for (int scene = 0; scene < 60; ++scene) {
        const double scale = std::pow(10.0, -4.0 + 8.0 * (scene % 9) / 8.0);
        std::vector<PolytopeBounds> boxes;
        const int clusters = 1 + scene % 7;
        for (int c = 0; c < clusters; ++c) {
            const Vec3 centre =
                scale * Vec3(Uniform(rng, -50, 50), Uniform(rng, -5, 5), Uniform(rng, -50, 50));
            for (int k = 0; k < 1 + (scene * 37 + c * 11) % 300; ++k) {
                const Vec3 at = centre + scale * Vec3(Uniform(rng, -3, 3), Uniform(rng, 0, 2),
                                                      Uniform(rng, -3, 3));
                const Vec3 half = scale * Vec3(Uniform(rng, 0.01, 1), Uniform(rng, 0.01, 1),
                                               Uniform(rng, 0.01, 1));
                // One box in fifty is flat, so empty.
                const Vec3 hi =
                    k % 50 == 49 ? Vec3(at + half - Vec3(2 * half.x(), 0, 0)) : Vec3(at + half);
                boxes.push_back(PolytopeBounds::OfBox(Aabb{at - half, hi}));
            }
        }
        const ObjectTree tree(boxes);
        for (int set = 0; set < 20; ++set) {
            std::vector<PlaneTest> planes;
            const int count = set == 19 ? 70 : 1 + set % 8;
            for (int p = 0; p < count; ++p) {
                const Vec3 n = testing::RandomUnit(rng);
                const PolytopeBounds& near = boxes[rng() % boxes.size()];
                const Vec3 through = near.empty() ? Vec3::Zero() : Vec3(0.5 * (near.lo + near.hi));
                Vec4 plane(n.x(), n.y(), n.z(), -n.dot(through) + scale * Uniform(rng, -8, 8));
                if (p == 5) plane = Vec4(0, 0, 0, set % 2 ? 1.0 : -1.0);  // at infinity
                if (p == 6 && set % 5 == 0) plane.w() = std::numeric_limits<double>::quiet_NaN();
                planes.emplace_back(plane);
            }
            std::vector<char> possible;
            tree.MarkPossible(planes, possible);
            const std::vector<char> expected = EveryBoxAlone(boxes, planes);
            ASSERT_EQ(possible.size(), expected.size());
            for (std::size_t i = 0; i < boxes.size(); ++i) {
                ASSERT_EQ(possible[i], expected[i])
                    << "scene " << scene << " set " << set << " box " << i;
                rejected += !expected[i];
                kept += expected[i];
            }
        }
    }
    EXPECT_GT(rejected, 50000);
    EXPECT_GT(kept, 20000);
}

// Centres over many scales (ten boxes at each power of two from 2^-1000 to 2^999), which a split
// at the middle of the centres' extent peels one scale at a time, and a uniform field: the depth
// stays within the median fallback's bound, log_{8/7} of the count.
TEST(ObjectTree, StaysShallowOnCentresOverManyScales) {
    std::vector<PolytopeBounds> spread;
    for (int k = 0; k < 20000; ++k) {
        const double x = std::ldexp(1.0, k % 2000 - 1000);
        spread.push_back(
            PolytopeBounds::OfBox(Aabb{Vec3(x, 0, k % 10), Vec3(1.5 * x, 1, k % 10 + 1)}));
    }
    const double bound = std::log(20000.0) / std::log(8.0 / 7.0) + 2.0;
    EXPECT_LE(ObjectTree(spread).depth(), bound);

    std::mt19937_64 rng(2978);
    std::vector<PolytopeBounds> field;
    for (int k = 0; k < 20000; ++k) {
        const Vec3 at(Uniform(rng, -100, 100), 0, Uniform(rng, -100, 100));
        field.push_back(PolytopeBounds::OfBox(Aabb{at, at + Vec3(0.5, 1, 0.5)}));
    }
    EXPECT_LE(ObjectTree(field).depth(), 2 * std::log2(20000.0));
    EXPECT_EQ(ObjectTree(std::vector<PolytopeBounds>{}).depth(), 0u);
}

}  // namespace
}  // namespace lixel::scheduling
