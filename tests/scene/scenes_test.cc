// Tests for lixel::eval built-in scenes and mesh builders (builtin_scenes.h, mesh_builders.h):
// determinism, triangle counts, closed flags, planes of interest, cameras and lights.
#include <gtest/gtest.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/mesh_builders.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>

namespace lixel::scene {
namespace {

bool SameMeshes(const Scene& a, const Scene& b) {
    if (a.meshes.size() != b.meshes.size()) return false;
    for (std::size_t i = 0; i < a.meshes.size(); ++i) {
        const Mesh& x = a.meshes[i];
        const Mesh& y = b.meshes[i];
        if (x.name != y.name || x.closed != y.closed || x.indices != y.indices ||
            x.positions != y.positions || x.normals != y.normals) {
            return false;
        }
    }
    return true;
}

TEST(MeshBuilders, TriangleCountsAndClosure) {
    const Mesh sphere = MakeSphere("s", Vec3::Zero(), 1.0, 7, 11);
    EXPECT_EQ(sphere.TriangleCount(), 2u * 11 * 6);
    EXPECT_TRUE(IsClosedByIndex(sphere));
    const Mesh torus = MakeTorus("t", Vec3::Zero(), 1.0, 0.3, 9, 5);
    EXPECT_EQ(torus.TriangleCount(), 2u * 9 * 5);
    EXPECT_TRUE(IsClosedByIndex(torus));
    const Mesh box = MakeBox("b", Aabb{Vec3::Zero(), Vec3(1, 2, 3)});
    EXPECT_EQ(box.TriangleCount(), 12u);
    EXPECT_TRUE(IsClosedByIndex(box));
    const Mesh lathe = MakeLathe("l", Vec3::Zero(), {{0.5, 0}, {0.7, 1}, {0.2, 2}}, 8);
    EXPECT_EQ(lathe.TriangleCount(), 8u * 2 + 2u * 8 * 2);
    EXPECT_TRUE(IsClosedByIndex(lathe));
    const Mesh quad = MakeQuad("q", Vec3::Zero(), Vec3::UnitX(), -Vec3::UnitZ(), 3);
    EXPECT_EQ(quad.TriangleCount(), 18u);
    EXPECT_FALSE(IsClosedByIndex(quad));
    EXPECT_FALSE(IsClosedByPosition(quad));
}

// Outward orientation: the signed volume (divergence theorem) is positive and matches the solid.
double SignedVolume(const Mesh& m) {
    double v = 0.0;
    for (std::size_t t = 0; t < m.TriangleCount(); ++t) {
        const Vec3 a = m.positions[m.indices[3 * t]].cast<double>();
        const Vec3 b = m.positions[m.indices[3 * t + 1]].cast<double>();
        const Vec3 c = m.positions[m.indices[3 * t + 2]].cast<double>();
        v += a.dot(b.cross(c)) / 6.0;
    }
    return v;
}

TEST(MeshBuilders, SolidsFaceOutward) {
    EXPECT_NEAR(SignedVolume(MakeBox("b", Aabb{Vec3::Zero(), Vec3(1, 2, 3)})), 6.0, 1e-5);
    const double sphere = SignedVolume(MakeSphere("s", Vec3(1, 2, 3), 1.0, 64, 128));
    EXPECT_NEAR(sphere, 4.0 / 3.0 * std::numbers::pi, 2e-3 * sphere);
    const double torus = SignedVolume(MakeTorus("t", Vec3::Zero(), 1.0, 0.25, 128, 64));
    const double torus_exact = 2.0 * std::numbers::pi * std::numbers::pi * 1.0 * 0.25 * 0.25;
    EXPECT_NEAR(torus, torus_exact, 5e-3 * torus_exact);
    const double cylinder = SignedVolume(MakeLathe("c", Vec3::Zero(), {{1, 0}, {1, 2}}, 256));
    EXPECT_NEAR(cylinder, 2.0 * std::numbers::pi, 1e-3 * cylinder);
    // Front face of a quad: edge_u x edge_v.
    const Mesh quad = MakeQuad("q", Vec3::Zero(), Vec3::UnitX(), -Vec3::UnitZ());
    const Vec3 a = quad.positions[quad.indices[0]].cast<double>();
    const Vec3 n = (quad.positions[quad.indices[1]].cast<double>() - a)
                       .cross(quad.positions[quad.indices[2]].cast<double>() - a);
    EXPECT_GT(n.y(), 0.0);
}

TEST(MeshBuilders, SmoothSphereNormalsAreRadial) {
    const Mesh s = MakeSphere("s", Vec3(1, 2, 3), 2.0, 10, 20);
    ASSERT_EQ(s.normals.size(), s.positions.size());
    for (std::size_t i = 0; i < s.positions.size(); ++i) {
        const Eigen::Vector3f radial = (s.positions[i] - Eigen::Vector3f(1, 2, 3)).normalized();
        EXPECT_GT(radial.dot(s.normals[i]), 0.9999f);
    }
}

TEST(BuiltinScenes, DeterministicAndComplete) {
    for (const std::string& name : BuiltinSceneNames()) {
        SCOPED_TRACE(name);
        auto a = BuiltinScene(name);
        auto b = BuiltinScene(name);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_EQ(a->name, name);
        EXPECT_TRUE(SameMeshes(*a, *b));
        EXPECT_FALSE(a->meshes.empty());
        ASSERT_FALSE(a->planes.empty());
        EXPECT_TRUE(ValidateViewer(a->camera.Viewer(), a->camera.viewport).ok());
        for (const Mesh& m : a->meshes) {
            SCOPED_TRACE(m.name);
            // The closed flag is the truth about the topology.
            EXPECT_EQ(m.closed, IsClosedByIndex(m));
            EXPECT_TRUE(m.normals.empty() || m.normals.size() == m.positions.size());
            EXPECT_GT(m.TriangleCount(), 0u);
        }
        // The light is on the first plane's lit side.
        const Vec4& plane = a->planes.front().plane;
        EXPECT_GT(plane.dot(a->light), 0.0);
        const auto objects = a->Objects();
        ASSERT_EQ(objects.size(), a->meshes.size());
        EXPECT_EQ(objects.front().mesh, &a->meshes.front());
        // The first plane of interest is in view: its polygon (or the plane) meets the frustum.
        const Mat4 pixel = a->camera.PixelMatrix();
        const Vec3 target = a->camera.target;
        const Vec4 t = pixel * Point(target);
        EXPECT_GT(t.w(), 0.0);
    }
    EXPECT_FALSE(BuiltinScene("nope").ok());
    EXPECT_EQ(BuiltinScene("nope").error().field, "scene");
}

TEST(BuiltinScenes, FloorWallMatchesThePaper) {
    const Scene s = FloorWallScene();
    ASSERT_EQ(s.planes.size(), 2u);
    EXPECT_EQ(s.planes[0].name, "floor");
    EXPECT_EQ(s.planes[0].plane, Vec4(0, 1, 0, 0));
    EXPECT_EQ(s.planes[1].name, "wall");
    EXPECT_EQ(s.planes[1].plane, Vec4(0, 0, 1, 5));
    EXPECT_TRUE(s.planes[0].polygon.empty() && s.planes[1].polygon.empty());
    EXPECT_EQ(s.camera.viewport.width, 1024);
    EXPECT_EQ(s.light, Point(Vec3(4, 9, 3)));
    EXPECT_FALSE(s.meshes[0].closed);  // floor
    EXPECT_FALSE(s.meshes[1].closed);  // wall
    for (std::size_t i = 2; i < s.meshes.size(); ++i) EXPECT_TRUE(s.meshes[i].closed);
    // Shapes rest on (or above) the floor and in front of the wall at every time.
    for (const double time : {0.0, 0.37, 1.0, 2.5, 10.0}) {
        const Scene moved = FloorWallScene(time);
        for (std::size_t i = 2; i < moved.meshes.size(); ++i) {
            const Aabb b = moved.meshes[i].Bounds();
            EXPECT_GE(b.min.y(), -1e-6) << moved.meshes[i].name << " at " << time;
            EXPECT_GT(b.min.z(), -5.0);
        }
    }
    // Time moves the shapes and nothing else.
    const Scene later = FloorWallScene(0.4);
    EXPECT_EQ(later.meshes[0].positions, s.meshes[0].positions);
    EXPECT_NE(later.meshes[2].positions, s.meshes[2].positions);
}

TEST(BuiltinScenes, TableTopIsABoundedPlaneFirst) {
    const Scene s = TableFloorScene();
    ASSERT_EQ(s.planes.size(), 2u);
    const PlaneOfInterest& table = s.planes[0];
    EXPECT_EQ(table.name, "table");
    ASSERT_EQ(table.polygon.size(), 4u);
    const Vec3 n = table.plane.head<3>();
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(table.plane.dot(Point(table.polygon[i])), 0.0, 1e-12);
        const Vec3& a = table.polygon[i];
        const Vec3& b = table.polygon[(i + 1) % 4];
        const Vec3& c = table.polygon[(i + 2) % 4];
        EXPECT_GT((b - a).cross(c - b).dot(n), 0.0);  // convex, counter-clockwise
    }
    EXPECT_EQ(s.planes[1].name, "floor");
    EXPECT_TRUE(s.planes[1].polygon.empty());
    // The table-top mesh's top face lies on the plane.
    for (const Mesh& m : s.meshes) {
        if (m.name != "table top") continue;
        EXPECT_NEAR(m.Bounds().max.y(), -table.plane.w(), 1e-6);
    }
}

TEST(BuiltinScenes, SphereGridTriangleCountFollowsItsParameter) {
    for (const long target : {30'000L, 100'000L, 250'000L, 1'000'000L, 2'000'000L}) {
        const Scene s = SphereGridScene(target);
        const double count = static_cast<double>(s.TriangleCount());
        EXPECT_NEAR(count, double(target), 0.01 * double(target)) << target;
        EXPECT_EQ(s.meshes.size(), 101u);  // floor + 10 x 10 spheres
    }
    // Clamped to the stated range.
    EXPECT_NEAR(double(SphereGridScene(10).TriangleCount()), 30'000.0, 300.0);
}

TEST(BuiltinScenes, ThinPlatesMixOpenAndClosed) {
    const Scene s = ThinPlatesScene();
    int open = 0, closed = 0;
    for (const Mesh& m : s.meshes) (m.closed ? closed : open)++;
    EXPECT_GE(open, 3);    // floor and single-sided plates
    EXPECT_GE(closed, 2);  // 1 mm slabs
    for (const Mesh& m : s.meshes) {
        if (m.closed) {
            EXPECT_LT(m.Bounds().max.y() - m.Bounds().min.y(), 2e-3) << m.name;
        }
    }
}

TEST(BuiltinScenes, SphereTorusIsCoarseWithSmoothNormals) {
    const Scene s = SphereTorusScene();
    EXPECT_EQ(s.light.w(), 0.0);  // directional
    for (std::size_t i = 1; i < s.meshes.size(); ++i) {
        EXPECT_TRUE(s.meshes[i].closed);
        EXPECT_LE(s.meshes[i].TriangleCount(), 200u);
        EXPECT_EQ(s.meshes[i].normals.size(), s.meshes[i].positions.size());
    }
}

TEST(BuiltinScenes, PinsAreClosedLatheSolids) {
    const Scene s = PinsScene();
    int pins = 0;
    for (const Mesh& m : s.meshes) {
        if (m.name.rfind("pin", 0) != 0) continue;
        ++pins;
        EXPECT_TRUE(m.closed);
        EXPECT_NEAR(m.Bounds().min.y(), 0.0, 1e-6);
    }
    EXPECT_EQ(pins, 10);
}

}  // namespace
}  // namespace lixel::scene

namespace lixel::scene {
namespace {

// The smooth twins keep everything but their casters' tessellation: the same meshes in the same
// order, the floor identical, every caster closed with normals and within its coarse copy's
// bounds give or take the tessellation's chord error (outward: the coarse mesh's vertices lie
// on the smooth surface, so the finer one bulges out between them by at most the sagitta).
TEST(BuiltinScenes, SmoothTwinsRefineOnlyTheSmoothCasters) {
    for (const std::string name : {"sphere_torus", "pins"}) {
        auto coarse = BuiltinScene(name);
        ASSERT_TRUE(coarse.ok());
        const std::optional<Scene> fine = SmoothTwin(name, 8);
        ASSERT_TRUE(fine.has_value()) << name;
        const std::optional<Scene> same = SmoothTwin(name, 1);
        ASSERT_TRUE(same.has_value()) << name;
        ASSERT_EQ(fine->meshes.size(), coarse->meshes.size()) << name;
        EXPECT_EQ(fine->light, coarse->light) << name;
        EXPECT_EQ(fine->camera.Viewer(), coarse->camera.Viewer()) << name;
        for (std::size_t i = 0; i < coarse->meshes.size(); ++i) {
            const Mesh& c = coarse->meshes[i];
            const Mesh& f = fine->meshes[i];
            EXPECT_EQ(f.name, c.name);
            EXPECT_EQ(same->meshes[i].positions, c.positions) << name << " refinement 1";
            if (!c.closed) {
                EXPECT_EQ(f.positions, c.positions) << name << " " << c.name;
                continue;
            }
            EXPECT_TRUE(f.closed);
            EXPECT_EQ(f.normals.size(), f.positions.size());
            EXPECT_GT(f.TriangleCount(), 40 * c.TriangleCount()) << name << " " << c.name;
            const Aabb cb = c.Bounds(), fb = f.Bounds();
            EXPECT_LT((fb.min - cb.min).norm() + (fb.max - cb.max).norm(), 0.1 * cb.Diagonal())
                << name << " " << c.name;
        }
    }
    EXPECT_FALSE(SmoothTwin("floor_wall").has_value());
    // Only a scene with the built-in meshes has the twin: not one that merely shares the name.
    EXPECT_TRUE(SmoothTwinOf(SphereTorusScene()).has_value());
    Scene renamed = FloorWallScene();
    renamed.name = "pins";
    EXPECT_FALSE(SmoothTwinOf(renamed).has_value());
}

}  // namespace
}  // namespace lixel::scene
