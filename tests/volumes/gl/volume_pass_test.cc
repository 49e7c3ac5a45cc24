// Tests for lixel::volumes_gl (volume_pass.h, shaders/shadow_volume.*, volume_caps.*): GPU and
// CPU multiplicities agree on every edge; masks equal exact ray-cast visibility outside a
// one-pixel band, for z-pass and z-fail, point and directional lights, the eye in shadow;
// smooth volumes against the analytic sphere shadow; a light in a triangle's plane.
#include <lixel/render/gpu_scene.h>
#include <lixel/render/readback.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_silhouette.h>
#include <lixel/volumes/smooth_volume.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "../fixtures.h"
#include "gl_environment.h"

namespace lixel::volumes::gl {
namespace {

using volumes::testing::Merge;
using volumes::testing::Sphere;

// GPU patch multiplicities summed per edge against Arithmetic::kFloat on the CPU.
void ExpectGpuMatchesCpu(const std::vector<Mesh>& meshes, const Vec4& light, int max_opposites) {
    render::GlContext& context = testing::Context();
    auto scene = UploadVolumeScene(context, meshes, Vec3::Zero(), max_opposites);
    ASSERT_TRUE(scene.ok()) << scene.error().Message();
    auto gpu = testing::Pass().PatchMultiplicities(*scene, light);
    ASSERT_TRUE(gpu.ok()) << gpu.error().Message();
    std::vector<std::vector<int>> per_edge(scene->adjacency().size());
    for (std::size_t m = 0; m < per_edge.size(); ++m) {
        per_edge[m].assign(scene->adjacency()[m].edges.size(), 0);
    }
    for (std::size_t p = 0; p < gpu->size(); ++p) {
        const PatchEdge& e = scene->patch_edges()[p];
        per_edge[e.mesh][e.edge] += (*gpu)[p];
    }
    std::size_t silhouette = 0;
    for (std::size_t m = 0; m < per_edge.size(); ++m) {
        const auto cpu = ComputeMultiplicities(scene->adjacency()[m], light, Arithmetic::kFloat,
                                               scene->origin());
        ASSERT_EQ(cpu.size(), per_edge[m].size());
        for (std::size_t e = 0; e < cpu.size(); ++e) {
            EXPECT_EQ(per_edge[m][e], cpu[e]) << "mesh " << m << " edge " << e;
            silhouette += cpu[e] != 0;
        }
    }
    EXPECT_GT(silhouette, 0u);
}

TEST(VolumePassMultiplicity, GpuAgreesWithCpuOnEveryEdge) {
    const Mesh grid = volumes::testing::SphereGrid(3, 0.5, 12, 18);
    const Mesh fans = Merge(
        {volumes::testing::Fan({0.5, 1.5, 2.5}), volumes::testing::Fan({0.3, 1.9, 3.1, 4.4})});
    const Mesh open = Merge({volumes::testing::Square(2.0, 0.0),
                             volumes::testing::Cylinder(Vec3(0, 0.5, 0), 0.5, 1.0, 13)});
    for (const Vec4& light :
         {Vec4(2, 6, 1, 1), Vec4(-3, 4, 5, 1), Vec4(0.3, 1, 0.2, 0), Vec4(5, 0.2, 0.5, 1)}) {
        ExpectGpuMatchesCpu({grid}, light, 0);
        ExpectGpuMatchesCpu({fans, open}, light, 0);
    }
}

TEST(VolumePassMultiplicity, GpuAgreesWithCpuAwayFromTheOrigin) {
    // Issue 16.5: the GPU evaluates Alg. 4 on fl(p - origin); Arithmetic::kFloat reproduces it
    // only when given the same origin (at origin 0 it rounds the world coordinates instead).
    // Spheres 3e4 from the world origin, uploaded about their centre, each light in or next to
    // the plane of one triangle, where the rounding decides the sign.
    const Vec3 centre(3e4, 1e4, -2e4);
    const Mesh grid = volumes::testing::Merge(
        {Sphere(centre, 0.5, 12, 18), Sphere(centre + Vec3(1.5, 0, 0.5), 0.5, 12, 18)});
    const Vec3 origin = centre + Vec3(0.37, -0.21, 0.13);
    auto scene = UploadVolumeScene(testing::Context(), std::vector<Mesh>{grid}, origin);
    ASSERT_TRUE(scene.ok()) << scene.error().Message();
    const EdgeAdjacency& adj = scene->adjacency()[0];
    std::size_t world_differs = 0;
    std::size_t edges = 0;
    for (int i = 0; i < 8; ++i) {
        const std::size_t t = (53 * static_cast<std::size_t>(i) + 11) % adj.source.size();
        const Vec3 a = adj.points[adj.triangles[3 * t]].cast<double>();
        const Vec3 b = adj.points[adj.triangles[3 * t + 1]].cast<double>();
        const Vec3 c = adj.points[adj.triangles[3 * t + 2]].cast<double>();
        const Vec3 d = (7.0 + i) * (b - a) - (3.0 + 0.5 * i) * (c - a);
        const Vec4 light = i % 4 == 3 ? Vec4(d.x(), d.y(), d.z(), 0.0) : Point(a + d);
        auto gpu = testing::Pass().PatchMultiplicities(*scene, light);
        ASSERT_TRUE(gpu.ok()) << gpu.error().Message();
        std::vector<int> per_edge(adj.edges.size(), 0);
        for (std::size_t p = 0; p < gpu->size(); ++p) {
            per_edge[scene->patch_edges()[p].edge] += (*gpu)[p];
        }
        const auto twin = ComputeMultiplicities(adj, light, Arithmetic::kFloat, origin);
        const auto world = ComputeMultiplicities(adj, light, Arithmetic::kFloat);
        for (std::size_t e = 0; e < per_edge.size(); ++e) {
            EXPECT_EQ(per_edge[e], twin[e]) << "light " << i << " edge " << e;
            world_differs += per_edge[e] != world[e];
            ++edges;
        }
    }
    EXPECT_GT(world_differs, 0u);  // the scenario: rounding about another origin decides signs
    std::printf("[ measured ] %zu edges: the GPU differs from kFloat at origin 0 on %zu\n", edges,
                world_differs);
}

TEST(VolumePassMultiplicity, SplitEdgesAddUp) {
    // Patches of two opposite points: the four-triangle edge is split over two patches.
    const Mesh fans = Merge(
        {volumes::testing::Fan({0.3, 1.9, 3.1, 4.4}), volumes::testing::Fan({0.5, 1.5, 2.5})});
    auto scene = UploadVolumeScene(testing::Context(), std::vector<Mesh>{fans}, Vec3::Zero(), 2);
    ASSERT_TRUE(scene.ok());
    EXPECT_EQ(scene->patch_vertices(), 4);
    EXPECT_EQ(scene->split_edges(), 1u);  // both fans share their spine: one edge of 7
    ExpectGpuMatchesCpu({fans}, Vec4(5, 0.2, 0.5, 1), 2);
    ExpectGpuMatchesCpu({fans}, Vec4(-1, 3, 2, 1), 1);
}

TEST(VolumePassMultiplicity, PatchesArePaddedOnlyToTheirOwnEdge) {
    // Issue 16.6: one wide fan made every patch of the scene as large as its spine's. Each
    // patch now holds A, B and exactly its own opposite points.
    std::vector<double> thirty;
    std::vector<double> forty;
    for (int k = 0; k < 30; ++k) thirty.push_back(0.1 + 0.2 * k);
    for (int k = 0; k < 40; ++k) forty.push_back(0.05 + 0.15 * k);
    const Mesh sphere = Sphere(Vec3(0, 3, 0), 0.5, 8, 12);
    Mesh far_fan = volumes::testing::Fan(forty);
    for (Eigen::Vector3f& p : far_fan.positions) p += Eigen::Vector3f(4.0f, 0.0f, 0.0f);
    const std::vector<Mesh> meshes = {sphere, volumes::testing::Fan(thirty), far_fan};
    auto scene = UploadVolumeScene(testing::Context(), meshes, Vec3::Zero());
    ASSERT_TRUE(scene.ok()) << scene.error().Message();
    const auto per_patch =
        static_cast<std::size_t>(std::min(testing::Context().info().max_patch_vertices - 2,
                                          (testing::Context().info().max_tess_gen_level + 1) / 2));
    std::size_t needed = 0;
    for (const EdgeAdjacency& adj : scene->adjacency()) {
        for (const Edge& e : adj.edges) {
            const std::size_t chunks = (e.count + per_patch - 1) / per_patch;
            needed += 2 * chunks + e.count;
        }
    }
    EXPECT_EQ(scene->patch_index_count(), needed);
    std::printf("[ measured ] patch indices %zu, needed %zu (%zu patches)\n",
                scene->patch_index_count(), needed, scene->patch_count());
    for (const Vec4& light : {Vec4(2, 6, 1, 1), Vec4(5, 0.2, 0.5, 1), Vec4(0.3, 1, 0.2, 0)}) {
        ExpectGpuMatchesCpu(meshes, light, 0);
    }
}

TEST(VolumePassMultiplicity, RefusesImpossiblePatchSizes) {
    const Mesh square = volumes::testing::Square(1.0, 0.0);
    auto scene =
        UploadVolumeScene(testing::Context(), std::vector<Mesh>{square}, Vec3::Zero(), 1000);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().field, "max_opposites");
    scene = UploadVolumeScene(testing::Context(), std::vector<Mesh>{}, Vec3::Zero());
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().field, "meshes");
}

// --- masks ---------------------------------------------------------------------------------

struct MaskCase {
    std::vector<Mesh> meshes;
    Mat4 viewer;
    Viewport viewport{96, 96};
    Vec4 light;
    Vec3 origin = Vec3(0.25, 0.0, -0.5);  // camera-relative rendering is exercised
};

Mat4 Viewer(const Vec3& eye, const Vec3& target) {
    return Perspective(45.0 * std::numbers::pi / 180.0, 1.0, 0.1, 50.0) *
           LookAt(eye, target, Vec3::UnitY());
}

// The view ray through pixel (x, y)'s centre, from the near plane to the far plane, for the
// inverse of the viewer's pixel matrix.
struct PixelRay {
    Vec3 origin;
    Vec3 dir;
};
PixelRay RayThrough(const Mat4& inverse, int x, int y) {
    const Vec4 n = inverse * Vec4(x + 0.5, y + 0.5, 0.0, 1.0);
    const Vec4 f = inverse * Vec4(x + 0.5, y + 0.5, 1.0, 1.0);
    const Vec3 origin = n.head<3>() / n.w();
    return {origin, Vec3(f.head<3>() / f.w() - origin)};
}

// Per pixel: -1 no surface, 0 shadowed, 1 lit, by ray casting the merged meshes exactly.
std::vector<int> TruthMask(const MaskCase& c) {
    const Mesh all = Merge(c.meshes);
    const Mat4 inverse = PixelMatrix(c.viewer, c.viewport).inverse();
    std::vector<int> truth(static_cast<std::size_t>(c.viewport.width) * c.viewport.height);
    for (int y = 0; y < c.viewport.height; ++y) {
        for (int x = 0; x < c.viewport.width; ++x) {
            const auto [origin, dir] = RayThrough(inverse, x, y);
            const double t = volumes::testing::NearestHit(all, origin, dir);
            int& out = truth[static_cast<std::size_t>(y) * c.viewport.width + x];
            if (!std::isfinite(t)) {
                out = -1;
                continue;
            }
            const Vec3 p = origin + t * dir;
            out = volumes::testing::ShadowRayHits(all, p, c.light) > 0 ? 0 : 1;
        }
    }
    return truth;
}

// A truth value Compare skips (pixels a test does not judge).
constexpr int kIgnored = -2;

struct Comparison {
    int compared = 0;
    int wrong = 0;
    int shadowed = 0;
};

// Pixels whose 3 x 3 neighbourhood in the truth is uniform (outside a one-pixel band around
// every boundary, shadow or silhouette) must match exactly.
Comparison Compare(const MaskCase& c, const render::FloatImage& mask,
                   const std::vector<int>& truth) {
    Comparison out;
    const int w = c.viewport.width;
    const int h = c.viewport.height;
    for (int y = 1; y + 1 < h; ++y) {
        for (int x = 1; x + 1 < w; ++x) {
            const int v = truth[static_cast<std::size_t>(y) * w + x];
            if (v == kIgnored) continue;
            bool uniform = true;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    uniform = uniform && truth[static_cast<std::size_t>(y + dy) * w + x + dx] == v;
                }
            }
            if (!uniform) continue;
            const float m = mask.at(x, y);
            const int got = m == render::kNoSurface ? -1 : (m > 0.5f ? 1 : 0);
            ++out.compared;
            out.wrong += got != v;
            out.shadowed += v == 0;
        }
    }
    return out;
}

struct Rendered {
    render::FloatImage mask;
    VolumeRenderInfo info;
};

Rendered RenderMask(const MaskCase& c, CountingChoice counting) {
    render::GlContext& context = testing::Context();
    auto surfaces = render::UploadScene(context, c.meshes, c.origin);
    EXPECT_TRUE(surfaces.ok()) << surfaces.error().Message();
    auto volumes = UploadVolumeScene(context, c.meshes, c.origin);
    EXPECT_TRUE(volumes.ok()) << volumes.error().Message();
    VolumeRequest request;
    request.viewer = c.viewer;
    request.viewport = c.viewport;
    request.light = c.light;
    request.counting = counting;
    request.measure_overdraw = true;
    render::ViewImages images;
    auto info = testing::Pass().Render(*surfaces, *volumes, request, images);
    EXPECT_TRUE(info.ok()) << info.error().Message();
    auto mask = render::ReadMask(context, images);
    EXPECT_TRUE(mask.ok()) << mask.error().Message();
    return {*mask, *info};
}

MaskCase SquareOverFloor() {
    MaskCase c;
    Mesh plate = volumes::testing::Square(0.5, 1.2);
    for (Eigen::Vector3f& p : plate.positions) p += Eigen::Vector3f(0.2f, 0.0f, 0.1f);
    c.meshes = {volumes::testing::Square(4.0, 0.0), plate};
    c.viewer = Viewer(Vec3(0.0, 5.0, 5.0), Vec3(0.0, 0.0, 0.3));
    c.light = Point(Vec3(1.5, 6.0, 1.0));
    return c;
}

MaskCase SphereOverFloor() {
    MaskCase c;
    c.meshes = {volumes::testing::Square(4.0, 0.0), Sphere(Vec3(0, 1.3, 0), 0.6, 10, 16)};
    c.viewer = Viewer(Vec3(0.5, 4.5, 5.0), Vec3(0.0, 0.5, 0.0));
    c.light = Point(Vec3(1.5, 6.0, 1.0));
    return c;
}

void ExpectMaskExact(const MaskCase& c, CountingChoice counting,
                     std::optional<CountingMode> expected_mode, const char* name) {
    const Rendered r = RenderMask(c, counting);
    if (expected_mode) {
        EXPECT_EQ(r.info.mode, *expected_mode) << name;
    }
    const Comparison cmp = Compare(c, r.mask, TruthMask(c));
    EXPECT_GT(cmp.compared, c.viewport.width * c.viewport.height / 2) << name;
    EXPECT_GT(cmp.shadowed, 100) << name << ", light " << c.light.transpose();
    EXPECT_EQ(cmp.wrong, 0) << name << " (" << CountingModeName(r.info.mode) << ")";
    EXPECT_GT(r.info.overdraw, 0.0) << name;
}

TEST(VolumePassMask, SquareOccluderZPassAndZFail) {
    const MaskCase c = SquareOverFloor();
    ExpectMaskExact(c, CountingChoice::kAuto, CountingMode::kZPass, "square auto");
    ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "square z-fail");
    ExpectMaskExact(c, CountingChoice::kZPass, CountingMode::kZPass, "square z-pass");
}

TEST(VolumePassMask, SphereOverFloorPointAndDirectional) {
    MaskCase c = SphereOverFloor();
    ExpectMaskExact(c, CountingChoice::kAuto, CountingMode::kZPass, "sphere auto");
    ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "sphere z-fail");
    c.light = Vec4(0.4, 1.0, 0.3, 0.0);
    ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "sphere directional");
}

TEST(VolumePassMask, LightBehindTheViewerAndInsideTheView) {
    // Volumes whose far ends project through w = 0: the light behind the camera, and the light
    // in the view frustum in front of the camera (its volumes point away from the viewer).
    MaskCase c = SphereOverFloor();
    for (const Vec4& light :
         {Point(Vec3(4.0, 7.0, 8.0)), Point(Vec3(1.2, 2.6, -1.5)), Vec4(-0.2, 0.6, -1.0, 0.0)}) {
        c.light = light;
        ExpectMaskExact(c, CountingChoice::kAuto, std::nullopt, "light placement, auto");
        ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "light placement, z-fail");
    }
}

TEST(VolumePassMask, TorusShadowsItself) {
    // Non-convex: the tube shadows the far side of the ring and the floor through the hole.
    MaskCase c;
    c.meshes = {volumes::testing::Square(4.0, 0.0),
                volumes::testing::Torus(Vec3(0, 0.8, 0), 1.0, 0.35, 16, 10)};
    c.viewer = Viewer(Vec3(0.5, 4.0, 4.5), Vec3(0.0, 0.5, 0.0));
    c.light = Point(Vec3(2.5, 3.0, -1.0));
    ExpectMaskExact(c, CountingChoice::kAuto, std::nullopt, "torus auto");
    ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "torus z-fail");
}

TEST(VolumePassMask, SphereGrid) {
    MaskCase c;
    c.meshes = {volumes::testing::Square(6.0, 0.0), volumes::testing::SphereGrid(3, 0.5, 8, 12)};
    c.viewer = Viewer(Vec3(1.5, 6.0, 7.0), Vec3(1.5, 0.0, 1.5));
    c.light = Point(Vec3(4.0, 7.0, -1.0));
    ExpectMaskExact(c, CountingChoice::kAuto, CountingMode::kZPass, "grid auto");
    ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "grid z-fail");
}

TEST(VolumePassMask, EyeInShadowNeedsZFail) {
    // The camera sits under the plate, in its shadow, looking across the floor: z-pass counts
    // from a shadowed eye and inverts the shadows; the automatic choice must take z-fail.
    MaskCase c = SquareOverFloor();
    c.viewer = Viewer(Vec3(0.3, 0.6, 0.2), Vec3(-3.0, 0.0, -2.0));
    ExpectMaskExact(c, CountingChoice::kAuto, CountingMode::kZFail, "eye in shadow");
    const Rendered zpass = RenderMask(c, CountingChoice::kZPass);
    const Comparison wrong = Compare(c, zpass.mask, TruthMask(c));
    EXPECT_GT(wrong.wrong, wrong.compared / 4);
}

TEST(VolumePassMask, CastersCountedWithDifferentModesAddUp) {
    // The eye under the plate (z-fail), a sphere in the plate's shadow casting its own (z-pass),
    // the floor (z-pass): where the shadows overlap the pixel's count is a z-fail and a z-pass
    // count summed, exact because each is exact for its own volumes.
    MaskCase c = SquareOverFloor();
    c.meshes.push_back(Sphere(Vec3(-0.5, 0.3, -0.5), 0.25, 10, 16));
    c.viewer = Viewer(Vec3(0.3, 0.6, 0.2), Vec3(-3.0, 0.0, -2.0));
    const Rendered r = RenderMask(c, CountingChoice::kAuto);
    EXPECT_EQ(r.info.modes, (std::vector<CountingMode>{CountingMode::kZPass, CountingMode::kZFail,
                                                       CountingMode::kZPass}));
    ExpectMaskExact(c, CountingChoice::kAuto, CountingMode::kZFail, "mixed auto");
    ExpectMaskExact(c, CountingChoice::kZFail, CountingMode::kZFail, "mixed z-fail");
}

TEST(VolumePassMask, EyeInsideAVolumeBehindIt) {
    // Issue 16.1: the eye at the origin looking down -z, the light at (10, 0, 10), a triangle
    // 0.02 wide 0.07 behind the eye toward the light: its volume holds the eye but not the near
    // rectangle. A plate casts a visible shadow on the wall. The sliver must be counted z-fail
    // (the eye is in the z-pass proof's hull), the wall and the plate may stay z-pass, and
    // forced z-pass (no depth clamp: counted from the near plane) is right as well.
    const Vec3 light_point(10, 0, 10);
    MaskCase c;
    c.meshes = {
        volumes::testing::FacingSquare(Vec3(0, 0, -3), Vec3::UnitZ(), 3.0),
        volumes::testing::FacingSquare(Vec3(0.4, 0.1, -1.5), Vec3::UnitZ(), 0.3),
        volumes::testing::FacingTriangle(0.07 * light_point.normalized(), light_point, 0.02)};
    c.viewer = Perspective(45.0 * std::numbers::pi / 180.0, 1.0, 0.1, 50.0) *
               LookAt(Vec3::Zero(), Vec3(0, 0, -1), Vec3::UnitY());
    c.light = Point(light_point);
    const std::vector<int> truth = TruthMask(c);
    for (CountingChoice counting :
         {CountingChoice::kAuto, CountingChoice::kZPass, CountingChoice::kZFail}) {
        const Rendered r = RenderMask(c, counting);
        const Comparison cmp = Compare(c, r.mask, truth);
        EXPECT_GT(cmp.compared, c.viewport.width * c.viewport.height / 2);
        EXPECT_GT(cmp.shadowed, 100);
        EXPECT_EQ(cmp.wrong, 0) << "counting " << static_cast<int>(counting);
        std::printf("[ measured ] eye in a volume, counting %d (%s): %d wrong of %d\n",
                    static_cast<int>(counting), CountingModeName(r.info.mode), cmp.wrong,
                    cmp.compared);
        if (counting == CountingChoice::kAuto) {
            EXPECT_EQ(r.info.modes,
                      (std::vector<CountingMode>{CountingMode::kZPass, CountingMode::kZPass,
                                                 CountingMode::kZFail}));
            EXPECT_EQ(r.info.mode, CountingMode::kZFail);
        }
    }
}

TEST(VolumePassMask, DeepStacksDoNotWrapTheCount) {
    // Issue 16.2: under 128 stacked closed boxes (two faces each) or 256 open sheets a shadow ray
    // crosses 256 faces; an 8-bit wrapping count reads 0 there, lit. Judged on the floor only
    // (the stacks' own thin sides are all boundary).
    std::vector<Mesh> boxes;
    std::vector<Mesh> sheets;
    for (int i = 0; i < 128; ++i) {
        const double y = 1.0 + 0.012 * i;
        boxes.push_back(volumes::testing::Box(Vec3(-0.5, y, -0.5), Vec3(0.5, y + 0.006, 0.5)));
    }
    for (int i = 0; i < 256; ++i) sheets.push_back(volumes::testing::Square(0.5, 1.0 + 0.005 * i));
    for (const Mesh& stack : {Merge(boxes), Merge(sheets)}) {
        MaskCase c;
        c.meshes = {volumes::testing::Square(4.0, 0.0), stack};
        c.viewer = Viewer(Vec3(0.5, 4.5, 5.0), Vec3(0.0, 0.5, 0.0));
        c.light = Point(Vec3(1.5, 8.0, 1.0));
        std::vector<int> truth = TruthMask(c);
        // Keep floor pixels only: those whose view ray meets y = 0 before any stack face.
        const Mat4 inverse = PixelMatrix(c.viewer, c.viewport).inverse();
        for (int y = 0; y < c.viewport.height; ++y) {
            for (int x = 0; x < c.viewport.width; ++x) {
                const auto [o, d] = RayThrough(inverse, x, y);
                const double floor_t = -o.y() / d.y();
                const double stack_t = volumes::testing::NearestHit(stack, o, d);
                int& t = truth[static_cast<std::size_t>(y) * c.viewport.width + x];
                if (!(floor_t > 0.0 && floor_t < stack_t)) t = kIgnored;
            }
        }
        for (CountingChoice counting : {CountingChoice::kZPass, CountingChoice::kZFail}) {
            const Rendered r = RenderMask(c, counting);
            const Comparison cmp = Compare(c, r.mask, truth);
            EXPECT_GT(cmp.compared, 1000);
            EXPECT_GT(cmp.shadowed, 100);
            EXPECT_EQ(cmp.wrong, 0)
                << stack.positions.size() << " vertices, " << CountingModeName(r.info.mode);
            std::printf("[ measured ] %zu-triangle stack, %s: %d wrong of %d (%d shadowed)\n",
                        stack.TriangleCount(), CountingModeName(r.info.mode), cmp.wrong,
                        cmp.compared, cmp.shadowed);
        }
    }
}

TEST(VolumePassMask, LightInATrianglesPlaneCastsNothing) {
    // A vertical triangle whose plane holds the light: no shadow on the floor at all.
    MaskCase c;
    Mesh wall;
    wall.positions = {Eigen::Vector3f(-0.5f, 0.5f, 0.0f), Eigen::Vector3f(0.5f, 0.5f, 0.0f),
                      Eigen::Vector3f(0.0f, 1.5f, 0.0f)};
    wall.indices = {0, 1, 2};
    c.meshes = {volumes::testing::Square(4.0, 0.0), wall};
    c.viewer = Viewer(Vec3(0.0, 5.0, 5.0), Vec3(0.0, 0.0, 0.3));
    c.light = Point(Vec3(0.3, 6.0, 0.0));
    for (CountingChoice counting : {CountingChoice::kZPass, CountingChoice::kZFail}) {
        const Rendered r = RenderMask(c, counting);
        int shadowed = 0;
        for (float m : r.mask.pixels) shadowed += m == 0.0f;
        EXPECT_EQ(shadowed, 0);
    }
}

TEST(VolumePassMask, RefusesBadRequestsNamingTheField) {
    const MaskCase c = SquareOverFloor();
    render::GlContext& context = testing::Context();
    auto surfaces = render::UploadScene(context, c.meshes, c.origin);
    auto volumes = UploadVolumeScene(context, c.meshes, c.origin);
    auto elsewhere = UploadVolumeScene(context, c.meshes, Vec3::Zero());
    ASSERT_TRUE(surfaces.ok() && volumes.ok() && elsewhere.ok());
    VolumeRequest request;
    request.viewer = c.viewer;
    request.viewport = c.viewport;
    request.light = c.light;
    render::ViewImages images;
    auto field = [&](const VolumeScene& v, const VolumeRequest& r) {
        auto info = testing::Pass().Render(*surfaces, v, r, images);
        return info.ok() ? std::string("ok") : info.error().field;
    };
    EXPECT_EQ(field(*volumes, request), "ok");
    EXPECT_EQ(field(*elsewhere, request), "origin");
    VolumeRequest bad = request;
    bad.light = Vec4::Zero();
    EXPECT_EQ(field(*volumes, bad), "light");
    bad = request;
    bad.viewer = Mat4::Zero();
    EXPECT_EQ(field(*volumes, bad).rfind("viewer", 0), 0u);
    bad = request;
    bad.viewport = {0, 10};
    EXPECT_NE(field(*volumes, bad), "ok");
    // A volume without caps cannot be counted the z-fail way.
    auto adj = BuildEdgeAdjacency(c.meshes[1]);
    ASSERT_TRUE(adj.ok());
    auto sides = UploadVolumeMesh(
        context,
        ExtrudeSilhouetteVolume(*adj, ComputeMultiplicities(*adj, c.light), c.light, Caps::kNone),
        c.origin);
    ASSERT_TRUE(sides.ok());
    bad = request;
    bad.counting = CountingChoice::kZFail;
    auto info = testing::Pass().Render(*surfaces, *volumes, *sides, bad, images);
    ASSERT_FALSE(info.ok());
    EXPECT_EQ(info.error().field, "volume.caps");
}

// --- smooth silhouettes on the GPU ----------------------------------------------------------

TEST(VolumePassSmooth, SmoothVolumeFollowsTheAnalyticSphereShadow) {
    // A coarse sphere: its discrete shadow is a polygon, the true smooth sphere's a conic. On
    // floor pixels away from the conic by more than a pixel, the smooth volume must be right.
    const Vec3 centre(0, 1.5, 0);
    const double radius = 1.0;
    MaskCase c;
    const Mesh sphere = Sphere(centre, radius, 6, 8);
    const Mesh floor = volumes::testing::Square(4.0, 0.0);
    c.meshes = {floor, sphere};
    c.viewer = Viewer(Vec3(0.5, 8.0, 2.0), Vec3(0.3, 0.0, 0.0));
    c.viewport = {160, 160};
    c.light = Point(Vec3(0.6, 4.0, 0.4));
    render::GlContext& context = testing::Context();
    auto surfaces = render::UploadScene(context, std::vector<Mesh>{floor}, c.origin);
    ASSERT_TRUE(surfaces.ok());
    auto volumes = UploadVolumeScene(context, std::vector<Mesh>{sphere}, c.origin);
    ASSERT_TRUE(volumes.ok());
    SmoothOptions options;
    options.epsilon = 0.001;
    auto smooth = ComputeSmoothSilhouette(sphere, volumes->adjacency()[0], c.light, options);
    ASSERT_TRUE(smooth.ok());
    auto gpu_volume = UploadVolumeMesh(
        context,
        ExtrudeSmoothVolume(sphere, volumes->adjacency()[0], *smooth, c.light, Caps::kLightAndDark),
        c.origin);
    ASSERT_TRUE(gpu_volume.ok()) << gpu_volume.error().Message();
    VolumeRequest request;
    request.viewer = c.viewer;
    request.viewport = c.viewport;
    request.light = c.light;
    // Only the floor is drawn (the sphere would hide part of its own shadow). With the occluder
    // not drawn, z-pass (which relies on the occluder hiding what lies behind its light cap) does
    // not apply: z-fail, forced.
    request.counting = CountingChoice::kZFail;
    const Mat4 inverse = PixelMatrix(c.viewer, c.viewport).inverse();
    const Vec3 l = c.light.head<3>();
    const double alpha = std::asin(radius / (centre - l).norm());
    {
        render::ViewImages smooth_images;
        render::ViewImages discrete_images;
        ASSERT_TRUE(
            testing::Pass().Render(*surfaces, *volumes, *gpu_volume, request, smooth_images).ok());
        ASSERT_TRUE(testing::Pass().Render(*surfaces, *volumes, request, discrete_images).ok());
        auto smooth_mask = render::ReadMask(context, smooth_images);
        auto discrete_mask = render::ReadMask(context, discrete_images);
        ASSERT_TRUE(smooth_mask.ok() && discrete_mask.ok());
        int compared = 0;
        int smooth_wrong = 0;
        int discrete_wrong = 0;
        for (int y = 0; y < c.viewport.height; ++y) {
            for (int x = 0; x < c.viewport.width; ++x) {
                if (smooth_mask->at(x, y) == render::kNoSurface) continue;
                // The floor point under the pixel centre and its pixel footprint.
                auto floor_point = [&](double px, double py) {
                    const Vec4 n = inverse * Vec4(px, py, 0.0, 1.0);
                    const Vec4 f = inverse * Vec4(px, py, 1.0, 1.0);
                    const Vec3 o = n.head<3>() / n.w();
                    const Vec3 d = f.head<3>() / f.w() - o;
                    return Vec3(o + (-o.y() / d.y()) * d);
                };
                const Vec3 p = floor_point(x + 0.5, y + 0.5);
                const double footprint = (floor_point(x + 1.5, y + 0.5) - p).norm();
                const Vec3 to = (p - l).normalized();
                const double angle = std::acos(to.dot((centre - l).normalized()));
                const double distance = std::abs(angle - alpha) * (p - l).norm();
                if (distance < 1.5 * footprint) continue;  // one-pixel band around the conic
                ++compared;
                const bool truth_lit = angle >= alpha;
                smooth_wrong += (smooth_mask->at(x, y) > 0.5f) != truth_lit;
                discrete_wrong += (discrete_mask->at(x, y) > 0.5f) != truth_lit;
            }
        }
        EXPECT_GT(compared, 10000);
        EXPECT_EQ(smooth_wrong, 0);
        EXPECT_GT(discrete_wrong, 20);
        std::printf("[ measured ] smooth vs conic: %d wrong, discrete %d wrong, of %d pixels\n",
                    smooth_wrong, discrete_wrong, compared);
    }
}

}  // namespace
}  // namespace lixel::volumes::gl
