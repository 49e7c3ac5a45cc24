// Tests for lixel::volumes extrusion (extrusion.h, volume_count.h, counting_mode.h): Alg. 5's
// tessellation mapping, closed volumes (z-pass count == z-fail count), counts against shadow
// rays, and the choice between z-pass and z-fail.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/volumes/counting_mode.h>
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/volume_count.h>

#include <cstdlib>
#include <numbers>
#include <random>

#include "fixtures.h"

namespace lixel::volumes {
namespace {

TEST(ExtrusionCorner, TessellationMakesMultiplicityCopiesOfTheSideQuad) {
    // Paper 001 Fig. 1: with 2|m| - 1 segments the even ones are the quad A, C, D, B (finite
    // edge A-B, pushed edge C-D) in one orientation, the odd ones have zero area.
    for (int m = 1; m <= 32; ++m) {
        const auto quads = TessellatedSideQuads(m);
        ASSERT_EQ(quads.size(), static_cast<std::size_t>(2 * m - 1));
        for (std::size_t s = 0; s < quads.size(); ++s) {
            const auto& q = quads[s];
            if (s % 2 == 0) {
                // Cyclic rotation of (A, C, D, B) = (0, 2, 3, 1).
                const std::array<int, 4> side = {0, 2, 3, 1};
                bool rotation = false;
                for (int r = 0; r < 4; ++r) {
                    bool same = true;
                    for (int k = 0; k < 4; ++k) same = same && q[k] == side[(k + r) % 4];
                    rotation = rotation || same;
                }
                EXPECT_TRUE(rotation) << "m " << m << " segment " << s;
            } else {
                // Zero area: the cell's opposite corners coincide (C D / D C or B A / A B).
                EXPECT_EQ(q[0], q[2]) << "m " << m << " segment " << s;
                EXPECT_EQ(q[1], q[3]) << "m " << m << " segment " << s;
                EXPECT_NE(q[0], q[1]) << "m " << m << " segment " << s;
            }
        }
    }
    EXPECT_EQ(ExtrusionCorner(0, 0), 0);
    EXPECT_EQ(ExtrusionCorner(0, 1), 1);
    EXPECT_EQ(ExtrusionCorner(1, 0), 2);
    EXPECT_EQ(ExtrusionCorner(1, 1), 3);
}

struct Scene {
    Mesh mesh;
    Vec4 light;
};

std::vector<Scene> Scenes() {
    const Mesh sphere = testing::Sphere(Vec3(0, 1.5, 0), 1.0, 8, 12);
    const Mesh fans =
        testing::Merge({testing::Fan({0.5, 1.5, 2.5}), testing::Fan({0.3, 1.9, 3.1, 4.4})});
    return {
        {sphere, Vec4(2, 6, 1, 1)},
        {sphere, Vec4(0.4, 1, 0.3, 0)},
        {testing::Square(1.0, 1.0), Vec4(0.5, 5, 0.2, 1)},
        {testing::Merge({sphere, testing::Box(Vec3(2, 0.5, -1), Vec3(3, 1.5, 0))}),
         Vec4(-1, 7, 2, 1)},
        {fans, Vec4(5, 0.2, 0.5, 1)},
        {testing::Cylinder(Vec3(0, 0.5, 0), 0.7, 1.5, 9), Vec4(1, 4, -2, 1)},
    };
}

TEST(Extrusion, CapsCloseTheVolumeAndCountsMatchShadowRays) {
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (const Scene& scene : Scenes()) {
        auto adj = BuildEdgeAdjacency(scene.mesh);
        ASSERT_TRUE(adj.ok());
        const std::vector<int> m = ComputeMultiplicities(*adj, scene.light);
        const VolumeMesh closed =
            ExtrudeSilhouetteVolume(*adj, m, scene.light, Caps::kLightAndDark);
        const VolumeMesh sides = ExtrudeSilhouetteVolume(*adj, m, scene.light, Caps::kNone);
        long quads = 0;
        for (int x : m) quads += std::abs(x);
        EXPECT_EQ(sides.SideTriangles(), static_cast<std::size_t>(2 * quads));
        EXPECT_EQ(sides.CapTriangles(), 0u);
        EXPECT_EQ(closed.CapTriangles(), 2 * adj->stats.kept_triangles);
        EXPECT_EQ(closed.sides, sides.sides);
        // An eye high up and to the side, outside every volume.
        const Vec3 eye(7.3, 9.1, 8.7);
        ASSERT_EQ(testing::ShadowRayHits(scene.mesh, eye, scene.light), 0);
        int shadowed = 0;
        for (int i = 0; i < 400; ++i) {
            const Vec3 p(u(rng), 0.5 * u(rng) + 1.0, u(rng));
            const int truth = testing::ShadowRayHits(scene.mesh, p, scene.light);
            EXPECT_EQ(CountZFail(closed, eye, p), truth) << scene.mesh.name << " point " << i;
            EXPECT_EQ(CountZPass(closed, eye, p), truth) << scene.mesh.name << " point " << i;
            // Without caps, z-pass is right for points the eye sees (the light cap it would cross
            // otherwise is the occluder's own surface, which hides the point).
            const Vec4 eye_point(eye.x(), eye.y(), eye.z(), 1.0);
            if (testing::ShadowRayHits(scene.mesh, p, eye_point) == 0) {
                EXPECT_EQ(CountZPass(sides, eye, p), truth) << scene.mesh.name << " point " << i;
            }
            shadowed += truth > 0;
        }
        EXPECT_GT(shadowed, 10) << scene.mesh.name;
    }
}

TEST(Extrusion, ZFailIsRightWhereTheEyeIsInShadow) {
    // Z-pass counts relative to the eye; z-fail does not care where the eye is.
    const Scene scene = Scenes()[0];
    auto adj = BuildEdgeAdjacency(scene.mesh);
    ASSERT_TRUE(adj.ok());
    const VolumeMesh closed = ExtrudeSilhouetteVolume(
        *adj, ComputeMultiplicities(*adj, scene.light), scene.light, Caps::kLightAndDark);
    const Vec3 eye(-0.8, -1.0, -0.5);  // under the sphere, in its shadow
    const int eye_count = testing::ShadowRayHits(scene.mesh, eye, scene.light);
    ASSERT_GT(eye_count, 0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int i = 0; i < 200; ++i) {
        const Vec3 p(u(rng), u(rng), u(rng));
        const int truth = testing::ShadowRayHits(scene.mesh, p, scene.light);
        EXPECT_EQ(CountZFail(closed, eye, p), truth);
        EXPECT_EQ(CountZPass(closed, eye, p), truth - eye_count);
    }
}

TEST(CountingMode, ZPassOnlyWhenTheNearPlaneMeetsNoVolume) {
    auto adj = BuildEdgeAdjacency(testing::Sphere(Vec3(0, 1, 0), 1.0, 8, 12));
    ASSERT_TRUE(adj.ok());
    const EdgeAdjacency* meshes[] = {&*adj};
    const Mat4 projection = Perspective(std::numbers::pi / 3, 1.0, 0.1, 100.0);
    const Vec4 light(0, 10, 0, 1);
    // Looking at the sphere from the side, the light above: the pyramid from the near plane to
    // the light is clear of the sphere.
    const Mat4 side = projection * LookAt(Vec3(6, 1, 0), Vec3(0, 1, 0), Vec3::UnitY());
    auto mode = ChooseCountingMode(meshes, light, side);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZPass);
    // The eye under the sphere: the sphere lies between the near plane and the light.
    const Mat4 below = projection * LookAt(Vec3(0, -2, 0.5), Vec3(3, -2, 0), Vec3::UnitY());
    mode = ChooseCountingMode(meshes, light, below);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
    // Directional light from the side the viewer looks from.
    mode = ChooseCountingMode(meshes, Vec4(-1, 0.05, 0, 0), side);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
    // From above and behind the viewer: the prism from the near plane goes away from the sphere.
    mode = ChooseCountingMode(meshes, Vec4(0.5, 1, 0, 0), side);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZPass);
    // Parallel to the near plane the hull is flat and nothing can be proven: z-fail.
    mode = ChooseCountingMode(meshes, Vec4(0, 1, 0, 0), side);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
    EXPECT_FALSE(ChooseCountingMode(meshes, light, Mat4::Zero()).ok());
}

}  // namespace
}  // namespace lixel::volumes
