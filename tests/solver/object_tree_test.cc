// Tests for the scheduler's object tree (solver/src/object_tree.h, an internal header): which
// boxes a set of clip planes may keep part of, found in groups, must be what testing every box
// alone finds, and the tree stays shallow whatever the boxes' layout.
#include "object_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel::scheduling {
namespace {

using testing::Uniform;

// The Morton code's bits per axis (object_tree.cc): the curve adds at most three times as many
// levels above the midpoint splits.
constexpr int kMortonBitsForTest = 10;

// The scan the tree must reproduce: a box is possible when no plane's group test rejects it,
// among the first kKeepsNothingClips + 1 planes (the ones whose rejection the test's margin
// covers).
std::vector<char> EveryBoxAlone(const std::vector<PolytopeBounds>& boxes,
                                const std::vector<PlaneTest>& planes) {
    std::vector<char> possible;
    for (const PolytopeBounds& b : boxes) {
        bool kept = !b.empty();
        for (std::size_t p = 0; p < planes.size() && p <= kKeepsNothingClips; ++p) {
            kept = kept && !b.KeepsNothingOf(planes[p]);
        }
        possible.push_back(kept);
    }
    return possible;
}

// A seeded scene of clustered boxes at `scale` (one in fifty flat, so empty).
std::vector<PolytopeBounds> ClusteredBoxes(std::mt19937_64& rng, int scene, double scale) {
    std::vector<PolytopeBounds> boxes;
    const int clusters = 1 + scene % 7;
    for (int c = 0; c < clusters; ++c) {
        const Vec3 centre =
            scale * Vec3(Uniform(rng, -50, 50), Uniform(rng, -5, 5), Uniform(rng, -50, 50));
        for (int k = 0; k < 1 + (scene * 37 + c * 11) % 300; ++k) {
            const Vec3 at =
                centre + scale * Vec3(Uniform(rng, -3, 3), Uniform(rng, 0, 2), Uniform(rng, -3, 3));
            const Vec3 half =
                scale * Vec3(Uniform(rng, 0.01, 1), Uniform(rng, 0.01, 1), Uniform(rng, 0.01, 1));
            const Vec3 hi =
                k % 50 == 49 ? Vec3(at + half - Vec3(2 * half.x(), 0, 0)) : Vec3(at + half);
            boxes.push_back(PolytopeBounds::OfBox(Aabb{at - half, hi}));
        }
    }
    return boxes;
}

// Seeded set `set` of clip planes through the scene near its boxes, one at infinity, and (every
// fifth set) one not finite; set 19 has 70, past the 64 the tree masks.
std::vector<PlaneTest> SeededPlanes(std::mt19937_64& rng, const std::vector<PolytopeBounds>& boxes,
                                    double scale, int set) {
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
    return planes;
}

double SceneScale(int scene) { return std::pow(10.0, -4.0 + 8.0 * (scene % 9) / 8.0); }

// Seeded scenes of clustered boxes at every scale (empty ones among them), against sets of up to
// 70 planes (past the 64 the tree masks), planes through the scene, near its clusters, at
// infinity and not finite.
TEST(ObjectTree, MarksExactlyTheBoxesNoPlaneRejectsOverSeededScenes) {
    std::mt19937_64 rng(2977);
    int rejected = 0, kept = 0;
    for (int scene = 0; scene < 60; ++scene) {
        const double scale = SceneScale(scene);
        const std::vector<PolytopeBounds> boxes = ClusteredBoxes(rng, scene, scale);
        const ObjectTree tree(boxes);
        for (int set = 0; set < 20; ++set) {
            const std::vector<PlaneTest> planes = SeededPlanes(rng, boxes, scale, set);
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

// With mark_inside, the boxes every plane holds inside it (PolytopeBounds::InsideOf) are marked
// kInside, as testing every box alone finds, and each such box's polytope keeps all of itself
// for every plane (ConvexPolytope::Effect), also for planes through one of its corners.
TEST(ObjectTree, MarksInsideExactlyTheBoxesEveryPlaneHoldsAndTheirClipsKeepThemWhole) {
    std::mt19937_64 rng(2981);
    int inside = 0, touching = 0;
    for (int scene = 0; scene < 60; ++scene) {
        const double scale = SceneScale(scene);
        const std::vector<PolytopeBounds> boxes = ClusteredBoxes(rng, scene, scale);
        const ObjectTree tree(boxes);
        for (int set = 0; set < 20; ++set) {
            std::vector<PlaneTest> planes = SeededPlanes(rng, boxes, scale, set);
            // A plane through a corner of a box, facing into it: the box lies on the plane.
            const PolytopeBounds& b = boxes[rng() % boxes.size()];
            if (!b.empty() && set % 2 == 0) {
                const Vec3 n = testing::RandomUnit(rng);
                const Vec3 corner(n.x() > 0 ? b.lo.x() : b.hi.x(), n.y() > 0 ? b.lo.y() : b.hi.y(),
                                  n.z() > 0 ? b.lo.z() : b.hi.z());
                planes.insert(planes.begin(), PlaneTest(Vec4(n.x(), n.y(), n.z(), -n.dot(corner))));
            }
            std::vector<char> marks;
            tree.MarkPossible(planes, marks, true);
            const std::vector<char> possible = EveryBoxAlone(boxes, planes);
            ASSERT_EQ(marks.size(), boxes.size());
            for (std::size_t i = 0; i < boxes.size(); ++i) {
                const bool held = !boxes[i].empty() && std::all_of(planes.begin(), planes.end(),
                                                                   [&](const PlaneTest& p) {
                                                                       return boxes[i].InsideOf(p);
                                                                   });
                const char expected = !possible[i] ? 0 : held ? ObjectTree::kInside : 1;
                ASSERT_EQ(marks[i], expected)
                    << "scene " << scene << " set " << set << " box " << i;
                if (marks[i] != ObjectTree::kInside) continue;
                ++inside;
                const ConvexPolytope box = ConvexPolytope::FromBox(Aabb{boxes[i].lo, boxes[i].hi});
                for (const PlaneTest& p : planes) {
                    ASSERT_EQ(box.Effect(p), ClipEffect::kKeepsAll)
                        << "scene " << scene << " set " << set << " box " << i;
                }
                touching += &boxes[i] == &b && set % 2 == 0;
            }
        }
    }
    EXPECT_GT(inside, 20000);
    EXPECT_GT(touching, 5);
}

// KeepsNothingOf's margin covers the clips before the rejecting plane up to kKeepsNothingClips: a
// plane further down the list rejects nothing, however far the boxes lie past it.
TEST(ObjectTree, TrustsNoRejectionPastTheClipsItsMarginCovers) {
    std::vector<PolytopeBounds> boxes;
    for (int k = 0; k < 40; ++k) {
        boxes.push_back(PolytopeBounds::OfBox(Aabb{Vec3(k, 0, 0), Vec3(k + 0.5, 1, 1)}));
    }
    const ObjectTree tree(boxes);
    // Planes that keep every box whole (x >= -1), then one that keeps none of them (x >= 100).
    const auto planes = [](std::size_t before) {
        std::vector<PlaneTest> out(before, PlaneTest(Vec4(1, 0, 0, 1)));
        out.emplace_back(Vec4(1, 0, 0, -100));
        return out;
    };
    std::vector<char> marks;
    tree.MarkPossible(planes(kKeepsNothingClips), marks);
    EXPECT_TRUE(std::all_of(marks.begin(), marks.end(), [](char m) { return m == 0; }));
    tree.MarkPossible(planes(kKeepsNothingClips + 1), marks);
    EXPECT_TRUE(std::all_of(marks.begin(), marks.end(), [](char m) { return m == 1; }));
}

// A tree refit to moved boxes (frames of a scene whose objects move: a few far, most a little,
// some grown or shrunk) marks exactly what testing every moved box alone marks, frame after
// frame, while its groups are those of the first frame's boxes.
TEST(ObjectTree, RefitMarksExactlyTheMovedBoxesNoPlaneRejects) {
    std::mt19937_64 rng(2979);
    int refits = 0, rejected = 0, kept = 0;
    for (int scene = 0; scene < 30; ++scene) {
        const double scale = SceneScale(scene);
        std::vector<PolytopeBounds> boxes = ClusteredBoxes(rng, scene, scale);
        ObjectTree tree(boxes);
        for (int frame = 0; frame < 6; ++frame) {
            for (PolytopeBounds& b : boxes) {
                if (b.empty()) continue;
                const double reach = rng() % 20 == 0 ? 100.0 : 0.5;
                const Vec3 step =
                    scale * reach *
                    Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
                const Vec3 centre = 0.5 * (b.lo + b.hi) + step;
                const Vec3 half = 0.5 * (b.hi - b.lo) * Uniform(rng, 0.5, 2.0);
                // A sliver the move would round flat stays where it is: the same boxes empty.
                const PolytopeBounds moved =
                    PolytopeBounds::OfBox(Aabb{centre - half, centre + half});
                if (!moved.empty()) b = moved;
            }
            ASSERT_TRUE(tree.Refit(boxes)) << "scene " << scene << " frame " << frame;
            ++refits;
            for (int set = 0; set < 10; ++set) {
                const std::vector<PlaneTest> planes = SeededPlanes(rng, boxes, scale, set);
                std::vector<char> possible;
                tree.MarkPossible(planes, possible);
                const std::vector<char> expected = EveryBoxAlone(boxes, planes);
                ASSERT_EQ(possible, expected)
                    << "scene " << scene << " frame " << frame << " set " << set;
                for (const char e : expected) (e ? kept : rejected) += 1;
            }
        }
    }
    EXPECT_EQ(refits, 180);
    EXPECT_GT(rejected, 20000);
    EXPECT_GT(kept, 10000);
}

// Boxes of another count, or empty where they were not, have another hierarchy: the refit is
// refused and the tree still answers for the boxes it holds.
TEST(ObjectTree, RefitRefusesBoxesOfAnotherHierarchyAndKeepsItsOwn) {
    std::mt19937_64 rng(2980);
    const std::vector<PolytopeBounds> boxes = ClusteredBoxes(rng, 3, 1.0);
    ObjectTree tree(boxes);
    const double spread = tree.spread();
    std::vector<PolytopeBounds> fewer(boxes.begin(), boxes.end() - 1);
    EXPECT_FALSE(tree.Refit(fewer));
    std::vector<PolytopeBounds> emptied = boxes;
    const auto solid = std::find_if(emptied.begin(), emptied.end(),
                                    [](const PolytopeBounds& b) { return !b.empty(); });
    ASSERT_NE(solid, emptied.end());
    *solid = PolytopeBounds{};
    EXPECT_FALSE(tree.Refit(emptied));
    EXPECT_EQ(tree.spread(), spread);
    for (int set = 0; set < 10; ++set) {
        const std::vector<PlaneTest> planes = SeededPlanes(rng, boxes, 1.0, set);
        std::vector<char> possible;
        tree.MarkPossible(planes, possible);
        EXPECT_EQ(possible, EveryBoxAlone(boxes, planes)) << "set " << set;
    }
    // The same boxes refit: the same groups, the same spread.
    EXPECT_TRUE(tree.Refit(boxes));
    EXPECT_EQ(tree.spread(), spread);
}

// A tree reads the boxes it was built or refit over in place (a plan's own array): a kept tree
// is refit to the next plan's boxes after the last plan's are gone, so neither a refit nor a
// refused one may read them. Under AddressSanitizer (scripts/sanitize.sh) a read of the freed
// array is a reported error.
TEST(ObjectTree, RefitNeedsOnlyTheBoxesItIsGiven) {
    std::mt19937_64 rng(2981);
    auto first = std::make_unique<std::vector<PolytopeBounds>>(ClusteredBoxes(rng, 5, 1.0));
    ObjectTree tree(*first);
    std::vector<PolytopeBounds> next = *first;
    for (PolytopeBounds& b : next) {
        if (b.empty()) continue;
        const Vec3 step(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
        const PolytopeBounds moved = PolytopeBounds::OfBox(Aabb{b.lo + step, b.hi + step});
        if (!moved.empty()) b = moved;
    }
    first.reset();
    const std::vector<PolytopeBounds> fewer(next.begin(), next.end() - 1);
    EXPECT_FALSE(tree.Refit(fewer));
    ASSERT_TRUE(tree.Refit(next));
    for (int set = 0; set < 10; ++set) {
        const std::vector<PlaneTest> planes = SeededPlanes(rng, next, 1.0, set);
        std::vector<char> possible;
        tree.MarkPossible(planes, possible);
        EXPECT_EQ(possible, EveryBoxAlone(next, planes)) << "set " << set;
    }
}

// Boxes whose centres the Morton curve cannot order alike (object_tree.cc; 1 200 of them, past
// the 1 024 from which it orders them): most of them in one cell of a cube 1e300 across, centres
// that overflow to infinity, centres that coincide, and centres too close together for the cube
// to have a finite number of cells a unit. The marks are still what testing every box alone
// finds.
TEST(ObjectTree, MarksExactlyWhereTheCentresHaveNoCubeToOrderThemIn) {
    std::mt19937_64 rng(2983);
    std::vector<std::vector<PolytopeBounds>> scenes(4);
    int rejected = 0, kept = 0;
    for (int k = 0; k < 1200; ++k) {
        const double far = k % 4 == 0 ? 1e300 * Uniform(rng, -1, 1) : 0.0;
        const double tiny = k % 4 == 1 ? 1e-300 : 1.0;
        const Vec3 at(far + tiny * Uniform(rng, -3, 3), tiny * Uniform(rng, 0, 2),
                      tiny * Uniform(rng, -3, 3));
        const Vec3 half = (far != 0.0 ? 1e298 : tiny) * Vec3::Constant(Uniform(rng, 0.01, 1));
        scenes[0].push_back(PolytopeBounds::OfBox(Aabb{at - half, at + half}));
        // Corners at +-1.7e308: the centres' sums overflow.
        const Vec3 side(k % 2 ? 1.7e308 : -1.7e308, Uniform(rng, -3, 3), 0);
        const Vec3 wide = Vec3::Constant(1e300 * Uniform(rng, 0.01, 1));
        scenes[1].push_back(PolytopeBounds::OfBox(Aabb{side - wide, side + wide}));
        scenes[2].push_back(PolytopeBounds::OfBox(Aabb{-(1.0 + k) * half, (1.0 + k) * half}));
        // Centres 1e-309 apart, 1.2e-306 across in all: 1 024 cells over that overflow.
        const Vec3 close(1e-309 * k, 0, 0);
        const Vec3 around = Vec3::Constant(1e-300 * (1.0 + k));
        scenes[3].push_back(PolytopeBounds::OfBox(Aabb{close - around, close + around}));
    }
    for (std::size_t scene = 0; scene < scenes.size(); ++scene) {
        const std::vector<PolytopeBounds>& boxes = scenes[scene];
        EXPECT_EQ(std::count_if(boxes.begin(), boxes.end(),
                                [](const PolytopeBounds& b) { return !b.empty(); }),
                  1200);
        const ObjectTree tree(boxes);
        EXPECT_LE(tree.depth(),
                  3 * kMortonBitsForTest + std::log(1200.0) / std::log(8.0 / 7.0) + 2);
        for (int set = 0; set < 40; ++set) {
            const double scale = set % 2 ? 1.0 : 1e300;
            const std::vector<PlaneTest> planes = SeededPlanes(rng, boxes, scale, set);
            std::vector<char> possible;
            tree.MarkPossible(planes, possible);
            ASSERT_EQ(possible, EveryBoxAlone(boxes, planes))
                << "scene " << scene << " set " << set;
            for (const char p : possible) (p ? kept : rejected) += 1;
        }
    }
    std::printf("[ measured ] %d boxes rejected, %d kept\n", rejected, kept);
    EXPECT_GT(rejected, 5000);
    EXPECT_GT(kept, 5000);
}

// Centres over many scales (ten boxes at each power of two from 2^-1000 to 2^999), which a split
// at the middle of the centres' extent peels one scale at a time, and a uniform field: the depth
// stays within the Morton curve's levels (three a bit of its codes) over the median fallback's
// bound, log_{8/7} of the count.
TEST(ObjectTree, StaysShallowOnCentresOverManyScales) {
    std::vector<PolytopeBounds> spread;
    for (int k = 0; k < 20000; ++k) {
        const double x = std::ldexp(1.0, k % 2000 - 1000);
        spread.push_back(
            PolytopeBounds::OfBox(Aabb{Vec3(x, 0, k % 10), Vec3(1.5 * x, 1, k % 10 + 1)}));
    }
    const double bound = 3 * kMortonBitsForTest + std::log(20000.0) / std::log(8.0 / 7.0) + 2.0;
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
