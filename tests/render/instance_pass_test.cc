// Tests for posed scenes (gpu_scene.h, GpuScene::Pose) in every map pass and the view: the
// identity pose bit for bit as the unposed scene, a moved instance as the moved mesh uploaded,
// a mesh placed twice, non-casters out of the maps, non-receivers lit, bad poses by name.
#include <lixel/render/depth_pass.h>
#include <lixel/render/readback.h>
#include <lixel/render/silhouette_pass.h>
#include <lixel/solver/mesh_instance.h>

#include <cmath>
#include <utility>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

FloatImage Depth(GpuScene& scene, const LightMap& map, FaceSelection faces) {
    auto depth = testing::TheRenderer().depth().Render(scene, map, faces);
    EXPECT_TRUE(depth.ok()) << depth.error().Message();
    auto image = ReadDepth(testing::Context(), *depth);
    EXPECT_TRUE(image.ok());
    return std::move(image).value();
}

FloatImage SilhouettePoints(GpuScene& scene, const LightMap& map, const Vec4& light) {
    SilhouetteMap target;
    auto ok = testing::TheRenderer().silhouette().Render(scene, map, light, {},
                                                         testing::TheRenderer().depth(), target);
    EXPECT_TRUE(ok.ok()) << ok.error().Message();
    auto image = ReadSilhouettePoints(testing::Context(), target);
    EXPECT_TRUE(image.ok());
    return std::move(image).value();
}

GpuScene Upload(const std::vector<Mesh>& meshes, const Vec3& origin) {
    auto scene = UploadScene(testing::Context(), meshes, origin);
    EXPECT_TRUE(scene.ok()) << scene.error().Message();
    return std::move(scene).value();
}

Mat4 Translation(const Vec3& t) {
    Mat4 m = Mat4::Identity();
    m.topRightCorner<3, 1>() = t;
    return m;
}

// The mesh carried by `m` on the CPU; a mirror also turns each triangle's winding, so the solid
// keeps its outside counter-clockwise (what an instance's pose means).
Mesh Moved(Mesh mesh, const Mat4& m) {
    for (Eigen::Vector3f& p : mesh.positions) {
        p = (m.topLeftCorner<3, 3>() * p.cast<double>() + m.topRightCorner<3, 1>()).cast<float>();
    }
    if (Mirrors(m)) {
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
        }
    }
    return mesh;
}

TEST(InstancePass, TheIdentityPoseDrawsEveryPassBitForBitAsTheUnposedScene) {
    const TestScene s = testing::SphereOverFloor(64);
    const LightMap map = testing::UniformMap(s, 96 * 96);
    GpuScene scene = Upload(s.meshes, s.origin);
    const FloatImage depth = Depth(scene, map, FaceSelection::kBoth);
    const FloatImage second = Depth(scene, map, FaceSelection::kSecondDepth);
    const FloatImage points = SilhouettePoints(scene, map, s.light);
    ASSERT_FALSE(scene.posed());
    // Explicit identity instances take the per-draw path everywhere (the silhouette map draws
    // every instance's adjacency instead of the candidates), and still draw the same texels.
    ASSERT_TRUE(scene.Pose(IdentityInstances(s.meshes.size())).ok());
    ASSERT_TRUE(scene.posed());
    EXPECT_EQ(Depth(scene, map, FaceSelection::kBoth).pixels, depth.pixels);
    EXPECT_EQ(Depth(scene, map, FaceSelection::kSecondDepth).pixels, second.pixels);
    EXPECT_EQ(SilhouettePoints(scene, map, s.light).pixels, points.pixels);
    int edges = 0;
    for (std::size_t i = 0; i < points.pixels.size(); i += 2) edges += points.pixels[i] >= 0.0f;
    EXPECT_GT(edges, 50);  // the sphere's outline is there to compare
}

// Texels where two depth maps differ by more than `tolerance` stored-depth units.
int Differing(const FloatImage& a, const FloatImage& b, float tolerance) {
    int n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        n += std::abs(a.pixels[i] - b.pixels[i]) > tolerance;
    }
    return n;
}

TEST(InstancePass, AMovedMirroredOrTwicePlacedMeshDrawsAsThatMeshUploadedWhereItLies) {
    const TestScene s = testing::SphereOverFloor(64);
    const LightMap map = testing::UniformMap(s, 128 * 128);
    // Turned a quarter about y, mirrored in x and moved: a pose that changes every coordinate.
    Mat4 turn = Mat4::Identity();
    turn.topLeftCorner<3, 3>() << 0, 0, 1, 0, 1, 0, -1, 0, 0;
    const Vec3 centre(-0.2, 1.3, 0.2);
    const Mat4 about_centre = Translation(centre) * turn * Translation(-centre);
    Mat4 mirror = Mat4::Identity();
    mirror(0, 0) = -1.0;
    const Mat4 moved = Translation(Vec3(0.3, 0.15, -0.2)) * about_centre;
    const Mat4 mirrored = Translation(Vec3(-0.4, 0.0, 0.0)) * mirror;
    ASSERT_TRUE(Mirrors(mirrored));

    GpuScene posed = Upload(s.meshes, s.origin);
    std::vector<MeshInstance> instances = IdentityInstances(2);
    instances[1].object_to_world = moved;
    MeshInstance again;
    again.mesh = 1;
    again.object_to_world = mirrored;
    instances.push_back(again);
    ASSERT_TRUE(posed.Pose(instances).ok());

    // The same meshes moved on the CPU and uploaded, relative to the same origin.
    GpuScene baked =
        Upload({s.meshes[0], Moved(s.meshes[1], moved), Moved(s.meshes[1], mirrored)}, s.origin);
    for (FaceSelection faces : {FaceSelection::kBoth, FaceSelection::kSecondDepth}) {
        const FloatImage a = Depth(posed, map, faces);
        const FloatImage b = Depth(baked, map, faces);
        // Where both hold the same surface, the depths agree to float rounding of the vertices
        // (2^-20 of a stored depth here); coverage may flip only on the outlines' texels.
        EXPECT_LE(Differing(a, b, 1e-5f), 2 * (map.width + map.height)) << FaceSelectionName(faces);
        int covered = 0;
        for (float d : a.pixels) covered += d > 0.0f;
        EXPECT_GT(covered, map.width * map.height / 4);
    }
    // The mirrored sphere alone: its second depth is its far side (its winding turned with the
    // mirror, as the baked copy's was), texel for texel but on its outline; culling the wrong
    // side would draw its near side on every texel it covers.
    {
        std::vector<MeshInstance> alone = {again};
        ASSERT_TRUE(posed.Pose(alone).ok());
        GpuScene baked_alone = Upload({Moved(s.meshes[1], mirrored)}, s.origin);
        const FloatImage a = Depth(posed, map, FaceSelection::kSecondDepth);
        const FloatImage b = Depth(baked_alone, map, FaceSelection::kSecondDepth);
        int covered = 0, apart = 0;
        for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            if (a.pixels[i] <= 0.0f || b.pixels[i] <= 0.0f) continue;
            ++covered;
            apart += std::abs(a.pixels[i] - b.pixels[i]) > 1e-5f;
        }
        const FloatImage first_alone = Depth(posed, map, FaceSelection::kBoth);
        int behind_first = 0;
        for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            behind_first += a.pixels[i] > 0.0f && a.pixels[i] < first_alone.pixels[i] - 1e-5f;
        }
        // 344 texels covered, 0 apart and 344 behind; with the winding left unturned, 344 apart
        // and none behind.
        EXPECT_GT(covered, 150);
        EXPECT_LE(apart, covered / 10);
        EXPECT_GE(behind_first, covered * 9 / 10);
        ASSERT_TRUE(posed.Pose(instances).ok());
    }
    // The spheres' second depth is their far side: well behind the first depth on their texels.
    const FloatImage second = Depth(posed, map, FaceSelection::kSecondDepth);
    const FloatImage first = Depth(posed, map, FaceSelection::kBoth);
    int behind = 0;
    for (std::size_t i = 0; i < first.pixels.size(); ++i) {
        behind += first.pixels[i] > 0.0f && second.pixels[i] < first.pixels[i] - 1e-4f;
    }
    EXPECT_GT(behind, 200);
}

TEST(InstancePass, ANonCasterLeavesTheMapsAndANonReceiverIsLitWhereItFacesTheLight) {
    const TestScene s = testing::SquareOverFloor(64);
    const LightMap map = testing::UniformMap(s, 96 * 96);
    GpuScene scene = Upload(s.meshes, s.origin);
    std::vector<MeshInstance> floor_only = {IdentityInstances(2)[0]};
    ASSERT_TRUE(scene.Pose(floor_only).ok());
    const FloatImage floor = Depth(scene, map, FaceSelection::kBoth);
    std::vector<MeshInstance> shadowless = IdentityInstances(2);
    shadowless[1].casts = false;
    ASSERT_TRUE(scene.Pose(shadowless).ok());
    EXPECT_EQ(Depth(scene, map, FaceSelection::kBoth).pixels, floor.pixels);
    EXPECT_EQ(SilhouettePoints(scene, map, s.light).pixels,
              (scene.Pose(floor_only).value(), SilhouettePoints(scene, map, s.light).pixels));

    // The view: the square's shadow on the floor, then the floor made a non-receiver.
    const std::vector<PlannedMap> maps = {testing::Planned(map, {Pass::kDepth})};
    const auto view = [&](const std::vector<MeshInstance>& pose) {
        EXPECT_TRUE(scene.Pose(pose).ok());
        auto rendered = testing::TheRenderer().RenderMaps(scene, maps, s.light);
        EXPECT_TRUE(rendered.ok());
        auto images = testing::TheRenderer().RenderView(
            scene, *rendered,
            ViewSettings{s.viewer, s.viewport, s.light, ShadowMethod::kDepth, {}});
        EXPECT_TRUE(images.ok());
        return ReadMask(testing::Context(), *images).value();
    };
    const auto shadowed = [](const FloatImage& mask) {
        int n = 0;
        for (float v : mask.pixels) n += v == 0.0f;
        return n;
    };
    const FloatImage receiving = view(IdentityInstances(2));
    std::vector<MeshInstance> unshadowed = IdentityInstances(2);
    unshadowed[0].receives = false;
    const FloatImage lit = view(unshadowed);
    EXPECT_GT(shadowed(receiving), 100);
    // Only the square's own sides turned from the light stay dark; the floor is lit throughout.
    EXPECT_LT(shadowed(lit), shadowed(receiving) / 4);
    for (std::size_t i = 0; i < lit.pixels.size(); ++i) {
        if (receiving.pixels[i] != lit.pixels[i]) {
            EXPECT_EQ(lit.pixels[i], 1.0f) << i;
        }
    }
}

TEST(InstancePass, APoseNamingAMeshPastTheSceneIsRefusedAndTheSceneKeepsItsPose) {
    const TestScene s = testing::SquareOverFloor(32);
    GpuScene scene = Upload(s.meshes, s.origin);
    std::vector<MeshInstance> bad = IdentityInstances(2);
    bad[1].mesh = 2;
    auto r = scene.Pose(bad);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "instances[1].mesh");
    EXPECT_FALSE(scene.posed());
    EXPECT_EQ(scene.draws().size(), 2u);
}

}  // namespace
}  // namespace lixel::render
