// A kept object index (object_index.h) changes no plan. Frames of seeded rooms whose boxes move
// (most a little, some across the room), appear and vanish, planned with one index and without
// one, give plans equal in every field (plan_text.h, floats compared bit for bit); so do plans
// that share one index from several threads at once.
#include <gtest/gtest.h>
#include <lixel/solver/object_index.h>
#include <lixel/solver/scheduler.h>

#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "plan_text.h"
#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Uniform;
using Random = std::mt19937_64;

// A box standing on the floor of the room (or, one in four, floating anywhere in it).
SceneObject SeededBox(Random& rng, const Aabb& room, int i) {
    const double x = Uniform(rng, room.min.x(), room.max.x());
    const double z = Uniform(rng, room.min.z(), room.max.z());
    const double w = Uniform(rng, 0.02, 0.4), h = Uniform(rng, 0.02, 0.8);
    const double base = i % 4 == 3 ? Uniform(rng, room.min.y(), room.max.y() - h) : room.min.y();
    return testing::Box("box " + std::to_string(i), Vec3(x - w, base, z - w),
                        Vec3(x + w, base + h, z + w));
}

// The room with `count` seeded boxes beside its own objects.
PlanRequest BoxedRoom(Random& rng, int count) {
    PlanRequest r = testing::FloorWallRoomRequest(512 * 512);
    r.scene_bounds = Aabb{Vec3(-10, -0.1, -5.1), Vec3(10, 8, 10)};
    for (int i = 0; i < count; ++i) r.objects.push_back(SeededBox(rng, r.scene_bounds, i));
    return r;
}

// The next frame: every box moved (one in ten across the room, the rest by up to 5 cm), every
// fourth frame of a round a few boxes added or removed, and the viewer moved a little.
void NextFrame(Random& rng, PlanRequest& r, int frame) {
    const Aabb& room = r.scene_bounds;
    const std::size_t own = testing::FloorWallRoomObjects().size();
    for (std::size_t i = own; i < r.objects.size(); ++i) {
        if (rng() % 10 == 0) {
            r.objects[i] = SeededBox(rng, room, static_cast<int>(i));
            continue;
        }
        const Vec3 step(Uniform(rng, -0.05, 0.05), 0, Uniform(rng, -0.05, 0.05));
        r.objects[i].bounds.min += step;
        r.objects[i].bounds.max += step;
    }
    if (frame % 4 == 3) {
        const int change = static_cast<int>(rng() % 7) - 3;
        for (int k = 0; k < change; ++k) {
            r.objects.push_back(SeededBox(rng, room, static_cast<int>(r.objects.size())));
        }
        for (int k = 0; k > change && r.objects.size() > own; --k) r.objects.pop_back();
    }
    r.viewer =
        r.viewer * Translation(Vec3(Uniform(rng, -0.05, 0.05), 0, Uniform(rng, -0.05, 0.05)));
}

std::string Planned(const PlanRequest& r, std::shared_ptr<ObjectIndex> index) {
    PlanRequest with = r;
    with.object_index = std::move(index);
    return plan_text::PlanText(PlanShadowMaps(with));
}

TEST(ObjectIndex, PlansWithAKeptIndexEqualPlansWithout) {
    Random rng(2990);
    std::uint64_t frames = 0;
    for (int round = 0; round < 12; ++round) {
        PlanRequest r = BoxedRoom(rng, static_cast<int>(rng() % 300));
        r.passes.second_depth = round % 3 == 1;
        const auto index = std::make_shared<ObjectIndex>();
        for (int frame = 0; frame < 8; ++frame, ++frames) {
            const std::string alone = plan_text::PlanText(PlanShadowMaps(r));
            ASSERT_EQ(Planned(r, index), alone) << "round " << round << " frame " << frame;
            NextFrame(rng, r, frame);
        }
        // The first frame builds; frames of as many boxes refit, unless their groups spread.
        const ObjectIndex::Counts counts = index->counts();
        EXPECT_EQ(counts.builds + counts.refits, 8u) << "round " << round;
        EXPECT_GE(counts.builds, 1u);
        EXPECT_GE(counts.refits, 3u) << "round " << round;
        EXPECT_EQ(counts.busy, 0u);
    }
    EXPECT_EQ(frames, 96u);
}

// Boxes that leave their groups far behind (every box across the room each frame) spread the
// refit tree past kRebuildSpread times its build's: the index builds anew, and the plans stay
// those without it.
TEST(ObjectIndex, BuildsAnewWhenTheRefitGroupsSpread) {
    Random rng(2991);
    PlanRequest r = BoxedRoom(rng, 400);
    const auto index = std::make_shared<ObjectIndex>();
    const std::size_t own = testing::FloorWallRoomObjects().size();
    for (int frame = 0; frame < 4; ++frame) {
        ASSERT_EQ(Planned(r, index), plan_text::PlanText(PlanShadowMaps(r))) << "frame " << frame;
        for (std::size_t i = own; i < r.objects.size(); ++i) {
            r.objects[i] = SeededBox(rng, r.scene_bounds, static_cast<int>(i));
        }
    }
    EXPECT_EQ(index->counts().builds, 4u);
    EXPECT_EQ(index->counts().refits, 0u);
}

// Plans of several threads sharing one index: each is the plan without it, whichever thread
// holds the tree; a plan that finds it in use builds its own.
TEST(ObjectIndex, PlansSharingAnIndexAcrossThreadsEqualPlansWithout) {
    Random rng(2992);
    std::vector<PlanRequest> frames;
    PlanRequest r = BoxedRoom(rng, 250);
    for (int frame = 0; frame < 6; ++frame) {
        frames.push_back(r);
        NextFrame(rng, r, frame);
    }
    std::vector<std::string> alone;
    for (const PlanRequest& f : frames) alone.push_back(plan_text::PlanText(PlanShadowMaps(f)));
    const auto index = std::make_shared<ObjectIndex>();
    constexpr int kThreads = 4;
    std::vector<std::vector<std::string>> planned(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            for (int round = 0; round < 3; ++round) {
                for (const PlanRequest& f : frames) planned[t].push_back(Planned(f, index));
            }
        });
    }
    for (std::thread& t : threads) t.join();
    for (int t = 0; t < kThreads; ++t) {
        ASSERT_EQ(planned[t].size(), 3 * frames.size());
        for (std::size_t k = 0; k < planned[t].size(); ++k) {
            EXPECT_EQ(planned[t][k], alone[k % frames.size()]) << "thread " << t << " plan " << k;
        }
    }
    const ObjectIndex::Counts counts = index->counts();
    EXPECT_EQ(counts.builds + counts.refits + counts.busy, kThreads * 3 * frames.size());
}

// A scene first sent strewn over two kilometres, then gathered into the room with every box in a
// new place: each refit group now spans most of the room, though the sum of their diagonals is far
// below the strewn build's. For the extent of the boxes the groups are far looser than the
// build's, so the index builds anew, and the plans stay those without it.
TEST(ObjectIndex, BuildsAnewWhenAStrewnSceneIsGathered) {
    Random rng(2992);
    PlanRequest r = BoxedRoom(rng, 400);
    const std::size_t own = testing::FloorWallRoomObjects().size();
    for (std::size_t i = own; i < r.objects.size(); ++i) {
        Aabb& b = r.objects[i].bounds;
        const Vec3 strewn(99.0 * b.min.x(), 0.0, 99.0 * b.min.z());
        b.min += strewn;
        b.max += strewn;
    }
    const auto index = std::make_shared<ObjectIndex>();
    ASSERT_EQ(Planned(r, index), plan_text::PlanText(PlanShadowMaps(r)));
    for (std::size_t i = own; i < r.objects.size(); ++i) {
        r.objects[i] = SeededBox(rng, r.scene_bounds, static_cast<int>(i));
    }
    ASSERT_EQ(Planned(r, index), plan_text::PlanText(PlanShadowMaps(r)));
    EXPECT_EQ(index->counts().builds, 2u);
    EXPECT_EQ(index->counts().refits, 0u);
    // Boxes that move after that (one in ten across the room, the rest a little) refit the new
    // tree.
    NextFrame(rng, r, 0);
    ASSERT_EQ(Planned(r, index), plan_text::PlanText(PlanShadowMaps(r)));
    EXPECT_EQ(index->counts().builds, 2u);
    EXPECT_EQ(index->counts().refits, 1u);
}

// A scene with no objects (a room of planes alone) keeps an empty tree: the second plan refits it
// (fuzz_scheduler: its spread had read the root of a tree with no nodes).
TEST(ObjectIndex, PlansOfNoObjectsRefitAnEmptyTree) {
    PlanRequest r = testing::FloorWallRoomRequest(512 * 512);
    r.objects.clear();
    r.scene_bounds = Aabb{Vec3(-10, -0.1, -5.1), Vec3(10, 8, 10)};
    ASSERT_TRUE(PlanShadowMaps(r).ok());
    const auto index = std::make_shared<ObjectIndex>();
    for (int frame = 0; frame < 2; ++frame) {
        ASSERT_EQ(Planned(r, index), plan_text::PlanText(PlanShadowMaps(r))) << "frame " << frame;
    }
    EXPECT_EQ(index->counts().builds, 1u);
    EXPECT_EQ(index->counts().refits, 1u);
}

// A plan cancelled while it holds the index lets go of it: the next plan refits (or builds)
// rather than finding it busy.
TEST(ObjectIndex, ACancelledPlanLetsGoOfTheIndex) {
    Random rng(2993);
    PlanRequest r = BoxedRoom(rng, 200);
    const auto index = std::make_shared<ObjectIndex>();
    r.object_index = index;
    for (const int stop_at : {1, 2, 5, 20}) {
        PlanRequest stopped = r;
        int polls = 0;
        stopped.cancelled = [&] { return ++polls >= stop_at; };
        const Result<Plan> cancelled = PlanShadowMaps(stopped);
        ASSERT_FALSE(cancelled) << "stop at poll " << stop_at;
        EXPECT_EQ(cancelled.error().reason, kPlanCancelled);
    }
    const std::uint64_t leases = index->counts().builds + index->counts().refits;
    EXPECT_GE(leases, 1u) << "no cancel came after the index was taken";
    PlanRequest without = r;
    without.object_index = nullptr;
    ASSERT_EQ(Planned(r, index), plan_text::PlanText(PlanShadowMaps(without)));
    EXPECT_EQ(index->counts().busy, 0u);
    EXPECT_GT(index->counts().builds + index->counts().refits, leases);
}

// A plan that finds the index held by another plan (here: planned from inside the first one's
// cancellation poll, on another thread) builds its own tree, counts as busy, and plans the same.
TEST(ObjectIndex, APlanFindingTheIndexHeldBuildsItsOwnTree) {
    Random rng(2994);
    PlanRequest r = BoxedRoom(rng, 150);
    const std::string alone = plan_text::PlanText(PlanShadowMaps(r));
    const auto index = std::make_shared<ObjectIndex>();
    std::string beside;
    bool ran = false;
    PlanRequest first = r;
    first.object_index = index;
    // The index's counts move when the first plan takes it; from then on it holds it.
    first.cancelled = [&] {
        if (!ran && index->counts().builds == 1) {
            ran = true;
            std::thread other([&] { beside = Planned(r, index); });
            other.join();
        }
        return false;
    };
    EXPECT_EQ(plan_text::PlanText(PlanShadowMaps(first)), alone);
    ASSERT_TRUE(ran);
    EXPECT_EQ(beside, alone);
    EXPECT_EQ(index->counts().busy, 1u);
    EXPECT_EQ(index->counts().builds, 1u);
}

}  // namespace
}  // namespace lixel
