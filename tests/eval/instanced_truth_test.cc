// Tests for exact visibility over instanced scenes (ground_truth.h, RayScene's two levels):
// the posed animated room against the same frame baked, a second pose placed on the same
// meshes against one built afresh, non-casters and non-receivers, and refusals by name.
#include <gtest/gtest.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/scene/builtin_scenes.h>

#include <cstdlib>

namespace lixel::eval {
namespace {

using scene::Scene;

TruthRequest RequestFor(const Scene& s, int side) {
    TruthRequest request;
    request.viewer = s.camera.Viewer();
    request.viewport = {side, side};
    request.light = s.light;
    request.planes = s.planes;
    return request;
}

TruthRequest SquareRequestFor(Scene s, int side) {
    s.camera.viewport = {side, side};
    return RequestFor(s, side);
}

GroundTruth Trace(const RayScene& rays, const TruthRequest& request) {
    auto truth = ComputeGroundTruth(rays, request);
    EXPECT_TRUE(truth.ok()) << truth.error().Message();
    return std::move(truth).value();
}

TEST(InstancedTruth, ThePosedRoomSeesWhatTheBakedRoomSees) {
    for (double time : {0.0, 0.35, 1.7}) {
        const Scene posed = scene::FloorWallAnimated(time);
        const Scene baked = scene::FloorWallScene(time);
        auto two_level = RayScene::Build(posed.meshes, posed.instances);
        auto flat = RayScene::Build(baked.meshes);
        ASSERT_TRUE(two_level.ok() && flat.ok());
        EXPECT_TRUE(two_level->instanced());
        EXPECT_EQ(two_level->triangles(), flat->triangles());
        const TruthRequest request = SquareRequestFor(baked, 160);
        const GroundTruth a = Trace(*two_level, request);
        const GroundTruth b = Trace(*flat, request);
        // The shapes' vertices differ by float rounding (the baked mesh rounds its lifted
        // coordinates, the posed one carries them in double): a pixel may change only where a
        // shadow or outline edge crosses its centre, a few in a room's 25 600.
        int differ = 0, same_object = 0;
        for (std::size_t i = 0; i < a.state.size(); ++i) {
            differ += a.state[i] != b.state[i];
            same_object += a.object[i] == b.object[i];  // instance i places mesh i here
        }
        EXPECT_LE(differ, 40) << "time " << time;
        EXPECT_GE(same_object, static_cast<int>(a.state.size()) - 40) << "time " << time;
        EXPECT_GT(a.Count(Truth::kShadow), 1000);  // 1 209 to 1 405 at these times
    }
}

TEST(InstancedTruth, PlacingAnotherPoseEqualsBuildingItAfresh) {
    const Scene first = scene::FloorWallAnimated(0.0);
    const Scene second = scene::FloorWallAnimated(0.9);
    auto built = RayScene::Build(first.meshes, first.instances);
    ASSERT_TRUE(built.ok());
    auto placed = built->Place(second.instances);
    auto afresh = RayScene::Build(second.meshes, second.instances);
    ASSERT_TRUE(placed.ok() && afresh.ok());
    const TruthRequest request = SquareRequestFor(second, 128);
    const GroundTruth a = Trace(*placed, request);
    const GroundTruth b = Trace(*afresh, request);
    EXPECT_EQ(a.state, b.state);
    EXPECT_EQ(a.object, b.object);
    EXPECT_EQ(a.primitive, b.primitive);
    // And the first pose still traces as it did: the placed scene shares the meshes only.
    EXPECT_NE(Trace(*built, request).state, a.state);
}

TEST(InstancedTruth, ANonCasterCastsNothingAndANonReceiverIsLitWhereItFacesTheLight) {
    Scene s = scene::FloorWallAnimated(0.2);
    const TruthRequest request = SquareRequestFor(s, 128);
    // The sphere (mesh 2) placed a second time, last, so every other instance keeps its index.
    MeshInstance extra = s.instances[2];
    extra.object_to_world(0, 3) += 2.5;
    std::vector<MeshInstance> with = s.instances;
    with.push_back(extra);
    std::vector<MeshInstance> shadowless = with;
    shadowless.back().casts = false;
    auto rays = RayScene::Build(s.meshes, with);
    ASSERT_TRUE(rays.ok());
    const GroundTruth casting = Trace(*rays, request);
    const GroundTruth non_caster = Trace(*rays->Place(shadowless), request);
    const GroundTruth without = Trace(*rays->Place(s.instances), request);
    const int extra_id = static_cast<int>(with.size()) - 1;
    int seen = 0, darker = 0;
    for (std::size_t i = 0; i < casting.state.size(); ++i) {
        if (non_caster.object[i] == extra_id) {
            ++seen;  // still seen: a non-caster is drawn and shaded
            continue;
        }
        // Elsewhere the non-caster is as if absent.
        EXPECT_EQ(non_caster.state[i], without.state[i]) << i;
        darker += casting.state[i] == Truth::kShadow && without.state[i] == Truth::kLit;
    }
    EXPECT_GT(seen, 50);
    EXPECT_GT(darker, 50);  // casting, the extra sphere does shadow the room

    std::vector<MeshInstance> bare_floor = s.instances;
    bare_floor[0].receives = false;
    const GroundTruth lit_floor = Trace(*rays->Place(bare_floor), request);
    const GroundTruth shadowed = Trace(*rays->Place(s.instances), request);
    int floor = 0, was_shadow = 0;
    for (std::size_t i = 0; i < lit_floor.state.size(); ++i) {
        if (lit_floor.object[i] != 0) {
            EXPECT_EQ(lit_floor.state[i], shadowed.state[i]);
            continue;
        }
        ++floor;
        EXPECT_EQ(lit_floor.state[i], Truth::kLit) << i;  // the floor faces the light
        was_shadow += shadowed.state[i] == Truth::kShadow;
    }
    EXPECT_GT(floor, 1000);
    EXPECT_GT(was_shadow, 200);
}

TEST(InstancedTruth, BadPosesAreRefusedNamingTheInstance) {
    const Scene s = scene::FloorWallAnimated(0.0);
    std::vector<MeshInstance> bad = s.instances;
    bad[3].mesh = 99;
    auto r = RayScene::Build(s.meshes, bad);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "instances[3].mesh");
    bad = s.instances;
    bad[4].object_to_world(3, 0) = 1.0;
    r = RayScene::Build(s.meshes, bad);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "instances[4].object_to_world");
    std::vector<MeshInstance> none;
    r = RayScene::Build(s.meshes, none);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "instances");
    auto flat = RayScene::Build(s.meshes);
    ASSERT_TRUE(flat.ok());
    auto placed = flat->Place(s.instances);
    ASSERT_FALSE(placed.ok());
    EXPECT_EQ(placed.error().field, "instances");
}

}  // namespace
}  // namespace lixel::eval
