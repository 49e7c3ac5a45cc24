// A scene's edge adjacency is built once and shared (issue 16: "adjacency is cached per scene"):
// every call, from any thread, gets the one object the first call built; a mesh that cannot be
// built is named on every call; the cache is charged for it from the upload on.
#include <gtest/gtest.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/service/proto_convert.h>
#include <lixel/service/scene_adjacency.h>

#include <limits>
#include <thread>
#include <vector>

namespace lixel::service {
namespace {

TEST(SceneAdjacency, EveryCallSharesTheFirstBuild) {
    const SceneRecord record = MakeSceneRecord(scene::FloorWallScene());
    std::vector<const MeshAdjacency*> seen(4, nullptr);
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < seen.size(); ++i) {
        threads.emplace_back([&, i] {
            auto got = record.adjacency->Get(record.scene.meshes);
            if (got.ok()) seen[i] = got->get();
        });
    }
    for (std::thread& t : threads) t.join();
    ASSERT_NE(seen[0], nullptr);
    for (const MeshAdjacency* s : seen) EXPECT_EQ(s, seen[0]);
    auto again = record.adjacency->Get(record.scene.meshes);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again->get(), seen[0]);
    ASSERT_EQ((*again)->size(), record.scene.meshes.size());
    for (std::size_t i = 0; i < record.scene.meshes.size(); ++i) {
        EXPECT_EQ((**again)[i].stats.input_triangles, record.scene.meshes[i].indices.size() / 3);
    }
    // A copy of the record (the same meshes) shares it too.
    const SceneRecord copy = record;
    EXPECT_EQ(copy.adjacency->Get(copy.scene.meshes)->get(), seen[0]);
}

TEST(SceneAdjacency, AMeshThatCannotBeBuiltIsNamedOnEveryCall) {
    scene::Scene scene = scene::FloorWallScene();
    scene.meshes[1].positions[0].x() = std::numeric_limits<float>::quiet_NaN();
    const SceneRecord record = MakeSceneRecord(std::move(scene));
    for (int call = 0; call < 2; ++call) {
        auto got = record.adjacency->Get(record.scene.meshes);
        ASSERT_FALSE(got.ok());
        EXPECT_EQ(got.error().field, "meshes[1].positions[0]");
    }
}

TEST(SceneAdjacency, TheCacheIsChargedForItsBound) {
    const SceneRecord record = MakeSceneRecord(scene::FloorWallScene());
    std::uint64_t bound = 0;
    std::uint64_t mesh_bytes = 0;
    for (const Mesh& m : record.scene.meshes) {
        bound += AdjacencyBytesBound(m);
        mesh_bytes += 12 * m.positions.size() + 12 * m.normals.size() + 4 * m.indices.size();
    }
    EXPECT_GE(record.bytes, mesh_bytes + bound);
    // The bound holds what the build allocates.
    auto built = record.adjacency->Get(record.scene.meshes);
    ASSERT_TRUE(built.ok());
    std::uint64_t used = 0;
    for (const volumes::EdgeAdjacency& a : **built) {
        used += a.points.size() * sizeof(a.points[0]) + 4 * (a.welded.size() +
                a.representative.size() + a.triangles.size() + a.source.size() +
                a.opposite.size() + a.opposite_triangle.size() + a.triangle_edges.size()) +
                a.edges.size() * sizeof(volumes::Edge);
    }
    EXPECT_LE(used, bound);
}

}  // namespace
}  // namespace lixel::service
