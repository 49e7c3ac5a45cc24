// The scene's smooth-volume cache (smooth_volume_cache.h): a pose that moves some instances under
// the same light rebuilds only their parts, and whatever it reuses, the volume it answers is the
// one a fresh ExtrudeSceneVolume builds, point for point and index for index.
#include <gtest/gtest.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/service/smooth_volume_cache.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/scene_volume.h>

#include <chrono>

namespace lixel {
namespace {

struct Room {
    scene::Scene scene = scene::FloorWallAnimated(0.0);
    std::vector<volumes::EdgeAdjacency> adjacency;
    Room() {
        for (const Mesh& mesh : scene.meshes) {
            adjacency.push_back(volumes::BuildEdgeAdjacency(mesh).value());
        }
    }
};

void ExpectSame(const volumes::VolumeMesh& a, const volumes::VolumeMesh& b) {
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
        ASSERT_EQ(a.vertices[i], b.vertices[i]) << "vertex " << i;
    }
    EXPECT_EQ(a.sides, b.sides);
    EXPECT_EQ(a.caps, b.caps);
}

TEST(SmoothVolumeCache, WhateverItReusesItAnswersTheFreshVolume) {
    const Room room;
    const service::SmoothVolumeCache cache;
    volumes::SmoothOptions options;
    options.epsilon = 1e-3;
    const Vec4 light = room.scene.light;
    std::vector<MeshInstance> pose = scene::FloorWallAnimated(0.3).instances;
    ASSERT_GE(pose.size(), 5u);

    auto first = cache.Get(room.scene.meshes, room.adjacency, pose, light, options);
    ASSERT_TRUE(first.ok()) << first.error().Message();
    EXPECT_TRUE(first->built);
    auto again = cache.Get(room.scene.meshes, room.adjacency, pose, light, options);
    ASSERT_TRUE(again.ok());
    EXPECT_FALSE(again->built);
    EXPECT_EQ(again->volume, first->volume);

    // One shape moved, then the light: each answer is the fresh build's.
    pose[2].object_to_world(1, 3) += 0.25;
    auto moved = cache.Get(room.scene.meshes, room.adjacency, pose, light, options);
    ASSERT_TRUE(moved.ok());
    EXPECT_TRUE(moved->built);
    auto fresh =
        volumes::ExtrudeSceneVolume(room.scene.meshes, room.adjacency, pose, light, options);
    ASSERT_TRUE(fresh.ok());
    ExpectSame(*moved->volume, *fresh);

    const Vec4 other_light = light + Vec4(0.5, 0.0, -0.25, 0.0);
    auto relit = cache.Get(room.scene.meshes, room.adjacency, pose, other_light, options);
    ASSERT_TRUE(relit.ok());
    fresh =
        volumes::ExtrudeSceneVolume(room.scene.meshes, room.adjacency, pose, other_light, options);
    ASSERT_TRUE(fresh.ok());
    ExpectSame(*relit->volume, *fresh);

    // No pose: each mesh in place, as the flat build.
    auto flat = cache.Get(room.scene.meshes, room.adjacency, {}, light, options);
    ASSERT_TRUE(flat.ok());
    fresh = volumes::ExtrudeSceneVolume(room.scene.meshes, room.adjacency, light, options);
    ASSERT_TRUE(fresh.ok());
    ExpectSame(*flat->volume, *fresh);
    // A non-caster leaves its part out.
    pose[2].casts = false;
    auto fewer = cache.Get(room.scene.meshes, room.adjacency, pose, light, options);
    ASSERT_TRUE(fewer.ok());
    fresh = volumes::ExtrudeSceneVolume(room.scene.meshes, room.adjacency, pose, light, options);
    ASSERT_TRUE(fresh.ok());
    ExpectSame(*fewer->volume, *fresh);
}

// The smooth points' budget (SmoothOptions::max_points) is for every instance together, the
// parts kept from the last pose included: a pose that rebuilds one early instance under a budget
// one point short of the whole is refused, and one at exactly the whole is served.
TEST(SmoothVolumeCache, KeptPartsCountAgainstTheBudgetOfThePartsBuiltAnew) {
    const Room room;
    const service::SmoothVolumeCache cache;
    volumes::SmoothOptions options;
    options.epsilon = 1e-3;
    const Vec4 light = room.scene.light;
    std::vector<MeshInstance> pose = scene::FloorWallAnimated(0.3).instances;
    // Every part once, unbounded: the parts the next pose keeps.
    ASSERT_TRUE(cache.Get(room.scene.meshes, room.adjacency, pose, light, options).ok());

    const auto points_of = [&](const MeshInstance& instance) {
        volumes::SceneVolumeInfo info;
        EXPECT_TRUE(volumes::ExtrudeInstanceVolume(room.scene.meshes[instance.mesh], instance.mesh,
                                                   room.adjacency[instance.mesh],
                                                   instance.object_to_world, light, options, &info)
                        .ok());
        return instance.casts ? info.smooth_points : 0;
    };
    std::size_t first = pose.size();  // the first instance with smooth points
    for (std::size_t i = 0; i < pose.size() && first == pose.size(); ++i) {
        if (points_of(pose[i]) > 0) first = i;
    }
    ASSERT_LT(first, pose.size());
    pose[first].object_to_world(1, 3) += 0.01;  // rebuilt; every other part kept
    std::size_t total = 0, after = 0;
    for (std::size_t i = 0; i < pose.size(); ++i) {
        total += points_of(pose[i]);
        if (i > first) after += points_of(pose[i]);
    }
    ASSERT_GT(after, 0u);  // kept parts after the rebuilt one hold points

    volumes::SmoothOptions bounded = options;
    bounded.max_points = total - 1;
    auto refused = cache.Get(room.scene.meshes, room.adjacency, pose, light, bounded);
    ASSERT_FALSE(refused.ok());
    EXPECT_TRUE(refused.error().field.ends_with("options.max_points")) << refused.error().Message();
    bounded.max_points = total;
    auto served = cache.Get(room.scene.meshes, room.adjacency, pose, light, bounded);
    ASSERT_TRUE(served.ok()) << served.error().Message();
}

// A build polls its caller's cancellation between instances: cancelled, it ends naming the
// request and keeps nothing, so the next call builds the whole volume afresh.
TEST(SmoothVolumeCache, ACancelledBuildEndsBetweenInstancesAndKeepsNothing) {
    const Room room;
    const service::SmoothVolumeCache cache;
    const std::vector<MeshInstance> pose = scene::FloorWallAnimated(0.3).instances;
    int polls = 0;
    auto cancelled = cache.Get(room.scene.meshes, room.adjacency, pose, room.scene.light, {},
                               [&] { return ++polls > 2; });
    ASSERT_FALSE(cancelled.ok());
    EXPECT_EQ(cancelled.error().field, "request");
    EXPECT_EQ(polls, 3);
    auto built = cache.Get(room.scene.meshes, room.adjacency, pose, room.scene.light, {});
    ASSERT_TRUE(built.ok());
    EXPECT_TRUE(built->built);
    auto fresh =
        volumes::ExtrudeSceneVolume(room.scene.meshes, room.adjacency, pose, room.scene.light, {});
    ASSERT_TRUE(fresh.ok());
    ExpectSame(*built->volume, *fresh);
}

}  // namespace
}  // namespace lixel
