// Tests for lixel::volumes extrusion (extrusion.h, volume_count.h, counting_mode.h): Alg. 5's
// tessellation mapping, closed volumes (z-pass count == z-fail count), counts against shadow
// rays, and the choice between z-pass and z-fail.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/volumes/counting_mode.h>
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/volume_count.h>

#include <cstdio>
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
    // Parallel to the near plane the light and the near rectangle alone span a flat hull; with
    // the eye it is a solid prism, clear of the sphere (whose volume is the column below it).
    mode = ChooseCountingMode(meshes, Vec4(0, 1, 0, 0), side);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZPass);
    // The same light, the eye in the sphere's shadow looking across: the prism holds the sphere.
    const Mat4 under = projection * LookAt(Vec3(0.2, -3, 0), Vec3(4, -3, 1), Vec3::UnitY());
    mode = ChooseCountingMode(meshes, Vec4(0, 1, 0, 0), under);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
    EXPECT_FALSE(ChooseCountingMode(meshes, light, Mat4::Zero()).ok());
}

TEST(Extrusion, CapsAgreeWithTheSidesWhateverTheArithmetic) {
    // Issue 16.5: a sphere 3e4 from the origin, each light (point or direction) in or next to
    // the plane of one of its triangles. The multiplicities the GPU computes
    // (Arithmetic::kFloat) and the exact ones disagree on such triangles; the caps must be
    // decided by the same predicate that gave the multiplicities, or the volume is not closed
    // (unbalanced edges; z-pass and z-fail counts differ).
    const Vec3 centre(3e4, 1e4, -2e4);
    const Mesh sphere = testing::Sphere(centre, 1.0, 16, 24);
    auto adj = BuildEdgeAdjacency(sphere);
    ASSERT_TRUE(adj.ok());
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> along(4.0, 40.0);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    std::size_t disagreeing = 0;
    std::size_t unbalanced = 0;
    int wrong = 0;
    int checked = 0;
    for (int i = 0; i < 12; ++i) {
        const std::size_t chosen = (37 * static_cast<std::size_t>(i) + 5) % adj->source.size();
        const Vec3 a = adj->points[adj->triangles[3 * chosen]].cast<double>();
        const Vec3 b = adj->points[adj->triangles[3 * chosen + 1]].cast<double>();
        const Vec3 c = adj->points[adj->triangles[3 * chosen + 2]].cast<double>();
        // Drawn in a fixed order: operands of one expression are evaluated in any order, and
        // GCC and clang pick different ones.
        const double along_b = along(rng);
        const double along_c = along(rng);
        const Vec3 in_plane = along_b * (b - a) - along_c * (c - a);
        const Vec4 light =
            i % 4 == 3 ? Vec4(in_plane.x(), in_plane.y(), in_plane.z(), 0.0) : Point(a + in_plane);
        // Points just past the centroid of every triangle the two arithmetics disagree on, seen
        // from the eye: the segment from the eye crosses that triangle's light cap.
        const Vec3 eye = centre + Vec3(7.3, 9.1, 8.7);
        std::vector<Vec3> points;
        for (std::size_t t = 0; t < adj->source.size(); ++t) {
            if (TriangleFacing(*adj, t, light, Arithmetic::kFloat) ==
                TriangleFacing(*adj, t, light)) {
                continue;
            }
            ++disagreeing;
            Vec3 g = Vec3::Zero();
            for (int k = 0; k < 3; ++k) g += adj->points[adj->triangles[3 * t + k]].cast<double>();
            g /= 3.0;
            points.push_back(g + 0.01 * (g - eye).normalized());
        }
        for (int k = 0; k < 100; ++k) points.push_back(centre + Vec3(u(rng), u(rng), u(rng)));
        for (const Arithmetic arithmetic : {Arithmetic::kFloat, Arithmetic::kExact}) {
            const VolumeMesh volume = ExtrudeSilhouetteVolume(
                *adj, ComputeMultiplicities(*adj, light, arithmetic), light, Caps::kLightAndDark);
            const testing::Watertightness w = testing::CountWatertightness(volume);
            unbalanced += w.unbalanced;
            EXPECT_EQ(w.unbalanced, 0u) << "light " << light.transpose();
            // The facings themselves, in the same arithmetic: sides and caps from one predicate.
            const testing::Watertightness from_facings =
                testing::CountWatertightness(ExtrudeSilhouetteVolume(
                    *adj, ComputeFacings(*adj, light, arithmetic), light, Caps::kLightAndDark));
            EXPECT_EQ(from_facings.unbalanced, 0u) << "light " << light.transpose();
            // A closed volume counts the same along any path: the faces crossed from the eye
            // to p plus the eye's own count (the eye may lie in the sphere's shadow) are p's
            // count, both taken along the one line from the eye through p.
            for (const Vec3& p : points) {
                checked += 1;
                const int at_eye = CountZFail(volume, 2.0 * eye - p, eye);
                wrong += CountZPass(volume, eye, p) + at_eye != CountZFail(volume, eye, p);
            }
        }
    }
    EXPECT_GT(disagreeing, 0u);  // the scenario: float and exact facings differ somewhere
    EXPECT_EQ(unbalanced, 0u);
    EXPECT_EQ(wrong, 0);
    std::printf(
        "[ measured ] 12 lights, %zu triangle facings differ between float and exact: %zu "
        "unbalanced edges, %d of %d points whose z-pass count plus the eye's differs from z-fail\n",
        disagreeing, unbalanced, wrong, checked);
}

TEST(CountingMode, ZPassOnlyWhenTheEyeIsOutsideEveryVolumeToo) {
    // Issue 16.1: the eye at the origin looking down -z, the light at (10, 0, 10), a triangle
    // 0.02 wide 0.07 behind the eye toward the light. Its volume holds the eye but not the near
    // rectangle, so McGuire's hull (light and near rectangle) misses it; z-pass counted from the
    // eye (CountZPass, or GL with depth clamp) is then one off everywhere.
    const Vec3 light_point(10, 0, 10);
    const Vec4 light = Point(light_point);
    const Mesh sliver = testing::FacingTriangle(0.07 * light_point.normalized(), light_point, 0.02);
    const Mesh wall = testing::FacingSquare(Vec3(0, 0, -3), Vec3::UnitZ(), 3.0);
    auto sliver_adj = BuildEdgeAdjacency(sliver);
    auto wall_adj = BuildEdgeAdjacency(wall);
    ASSERT_TRUE(sliver_adj.ok() && wall_adj.ok());
    const Mat4 viewer = Perspective(std::numbers::pi / 4, 1.0, 0.1, 50.0) *
                        LookAt(Vec3::Zero(), Vec3(0, 0, -1), Vec3::UnitY());
    const VolumeMesh volume = ExtrudeSilhouetteVolume(
        *sliver_adj, ComputeMultiplicities(*sliver_adj, light), light, Caps::kLightAndDark);
    int zpass_wrong = 0;
    for (int i = 0; i < 11; ++i) {
        for (int k = 0; k < 11; ++k) {
            const Vec3 p(-1.0 + 0.2 * i, -1.0 + 0.2 * k, -3.0);  // lit wall points in view
            ASSERT_EQ(testing::ShadowRayHits(sliver, p, light), 0);
            ASSERT_EQ(CountZFail(volume, Vec3::Zero(), p), 0);
            zpass_wrong += CountZPass(volume, Vec3::Zero(), p) != 0;
        }
    }
    EXPECT_EQ(zpass_wrong, 121);  // the scenario: counting from the eye is wrong everywhere
    const EdgeAdjacency* sliver_only[] = {&*sliver_adj};
    auto mode = ChooseCountingMode(sliver_only, light, viewer);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
    mode = ChooseCountingMode(volume, light, viewer);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
    // Per caster: the wall can still be counted z-pass.
    const EdgeAdjacency* both[] = {&*wall_adj, &*sliver_adj};
    auto modes = ChooseCountingModes(both, light, viewer);
    ASSERT_TRUE(modes.ok());
    EXPECT_EQ(*modes, (std::vector<CountingMode>{CountingMode::kZPass, CountingMode::kZFail}));
    mode = ChooseCountingMode(both, light, viewer);
    ASSERT_TRUE(mode.ok());
    EXPECT_EQ(*mode, CountingMode::kZFail);
}

TEST(CountingMode, ZPassChoiceIsSoundForRandomViewsAndLights) {
    // Whenever z-pass is chosen, counting from the eye (CountZPass) equals the shadow-ray truth:
    // no volume holds the eye. (Closed volumes, so the segments may pass through occluders.)
    const Mesh mesh =
        testing::Merge({testing::Sphere(Vec3(0, 1, 0), 1.0, 8, 12),
                        testing::Box(Vec3(2, 0, -1), Vec3(3, 1, 0)), testing::Square(6.0, -1.0)});
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    const EdgeAdjacency* meshes[] = {&*adj};
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> u(-4.0, 4.0);
    int zpass = 0;
    int zfail = 0;
    for (int view = 0; view < 300; ++view) {
        const Vec3 eye(u(rng), u(rng), u(rng));
        const Vec3 target(0.3 * u(rng), 1.0 + 0.3 * u(rng), 0.3 * u(rng));
        const Vec4 light = view % 3 == 0 ? Vec4(u(rng), u(rng), u(rng), 0.0)
                                         : Point(Vec3(u(rng), 4.0 + u(rng), u(rng)));
        if ((eye - target).norm() < 0.5) continue;
        const Mat4 viewer = Perspective(std::numbers::pi / 3, 1.0, 0.05, 100.0) *
                            LookAt(eye, target, Vec3::UnitY());
        auto mode = ChooseCountingMode(meshes, light, viewer);
        ASSERT_TRUE(mode.ok());
        if (*mode == CountingMode::kZFail) {
            ++zfail;
            continue;
        }
        ++zpass;
        const VolumeMesh closed = ExtrudeSilhouetteVolume(*adj, ComputeMultiplicities(*adj, light),
                                                          light, Caps::kLightAndDark);
        for (int i = 0; i < 20; ++i) {
            const Vec3 p(u(rng), u(rng), u(rng));
            ASSERT_EQ(CountZPass(closed, eye, p), testing::ShadowRayHits(mesh, p, light))
                << "view " << view << " point " << p.transpose();
        }
    }
    EXPECT_GT(zpass, 50);
    EXPECT_GT(zfail, 20);
    std::printf("[ measured ] random views: %d z-pass, %d z-fail\n", zpass, zfail);
}

}  // namespace
}  // namespace lixel::volumes
