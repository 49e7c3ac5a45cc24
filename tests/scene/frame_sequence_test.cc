// Tests for scene::SequenceFrame and SequenceCamera (frame_sequence.h): deterministic frames,
// the camera path's geometry, the animation only where the scene has one, bad options by name.
#include <gtest/gtest.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <numbers>

namespace lixel::scene {
namespace {

TEST(SequenceFrame, SameFrameSameSceneAndCamera) {
    SequenceOptions options;
    auto a = SequenceFrame("floor_wall", 17, options);
    auto b = SequenceFrame("floor_wall", 17, options);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->meshes.size(), b->meshes.size());
    for (std::size_t i = 0; i < a->meshes.size(); ++i) {
        EXPECT_EQ(a->meshes[i].positions, b->meshes[i].positions);
    }
    EXPECT_EQ(a->camera.Viewer(), b->camera.Viewer());
}

TEST(SequenceFrame, FloorWallMeshesStayAndTheirInstancesBounce) {
    SequenceOptions options;
    auto first = SequenceFrame("floor_wall", 0, options);
    auto later = SequenceFrame("floor_wall", 10, options);
    ASSERT_TRUE(first.ok() && later.ok());
    // The meshes are the same every frame: an engine uploads them once.
    ASSERT_EQ(first->meshes.size(), later->meshes.size());
    for (std::size_t i = 0; i < later->meshes.size(); ++i) {
        EXPECT_EQ(first->meshes[i].positions, later->meshes[i].positions) << i;
    }
    // Posed, each vertex is FloorWallScene's at that time up to float rounding (the instance
    // lifts the shape resting on the floor by its bounce height).
    const Scene at_time = FloorWallScene(10 / options.fps);
    ASSERT_EQ(later->instances.size(), at_time.meshes.size());
    for (std::size_t i = 0; i < later->instances.size(); ++i) {
        const MeshInstance& instance = later->instances[i];
        ASSERT_EQ(instance.mesh, i);
        EXPECT_TRUE(CheckInstanceMatrix(instance.object_to_world, "m").ok());
        const Mesh& rest = later->meshes[i];
        ASSERT_EQ(rest.positions.size(), at_time.meshes[i].positions.size());
        for (std::size_t v = 0; v < rest.positions.size(); ++v) {
            const Vec3 placed =
                (instance.object_to_world * Point(rest.positions[v].cast<double>())).head<3>();
            const Vec3 baked = at_time.meshes[i].positions[v].cast<double>();
            // Two float roundings of coordinates below 16 m: 2^-19 m each.
            EXPECT_LE((placed - baked).cwiseAbs().maxCoeff(), 0x1p-18) << i << " " << v;
        }
    }
    // Floor and wall hold still; at least three of the four shapes moved between the frames.
    EXPECT_EQ(first->instances[0].object_to_world, Mat4::Identity());
    EXPECT_EQ(later->instances[1].object_to_world, Mat4::Identity());
    int moved = 0;
    for (std::size_t i = 2; i < later->instances.size(); ++i) {
        moved += first->instances[i].object_to_world != later->instances[i].object_to_world;
    }
    EXPECT_GE(moved, 3);
    // A scene without animation has no instances and keeps its meshes; only the camera moves.
    auto table0 = SequenceFrame("table_floor", 0, options);
    auto table9 = SequenceFrame("table_floor", 9, options);
    ASSERT_TRUE(table0.ok() && table9.ok());
    EXPECT_TRUE(table0->instances.empty());
    for (std::size_t i = 0; i < table0->meshes.size(); ++i) {
        EXPECT_EQ(table0->meshes[i].positions, table9->meshes[i].positions);
    }
    EXPECT_NE(table0->camera.eye, table9->camera.eye);
}

TEST(SequenceCamera, OrbitsTheTargetWithinTheStatedAngleAndDolly) {
    const Camera base = FloorWallScene().camera;
    SequenceOptions options;
    options.frames = 61;
    const Vec3 base_offset = base.eye - base.target;
    double first_angle = 0.0, last_angle = 0.0;
    for (int f = 0; f < options.frames; ++f) {
        const Camera c = SequenceCamera(base, f, options);
        EXPECT_EQ(c.target, base.target);
        EXPECT_EQ(c.viewport.width, 512);
        const Vec3 offset = c.eye - c.target;
        const double t = f / 60.0;
        // Height over the target scales with the distance; the distance swings by the dolly.
        const double factor = 1.0 - options.dolly * std::sin(2.0 * std::numbers::pi * t);
        EXPECT_NEAR(offset.norm(), factor * base_offset.norm(), 1e-12);
        EXPECT_NEAR(offset.y(), factor * base_offset.y(), 1e-12);
        const double angle = std::atan2(offset.x(), offset.z()) -
                             std::atan2(base_offset.x(), base_offset.z());
        if (f == 0) first_angle = angle;
        if (f == options.frames - 1) last_angle = angle;
    }
    EXPECT_NEAR((last_angle - first_angle) * 180.0 / std::numbers::pi, options.orbit_degrees,
                1e-9);
    // The middle frame is the scene's own camera.
    EXPECT_LT((SequenceCamera(base, 30, options).eye - base.eye).norm(), 1e-12);
}

TEST(SequenceFrame, RefusesBadOptionsNamingTheField) {
    const auto field = [](const std::string& name, int frame, SequenceOptions o) {
        auto r = SequenceFrame(name, frame, o);
        return r.ok() ? std::string("ok") : r.error().field;
    };
    SequenceOptions o;
    EXPECT_EQ(field("floor_wall", 60, o), "frame");
    EXPECT_EQ(field("floor_wall", -1, o), "frame");
    EXPECT_EQ(field("no_such_scene", 0, o), "scene");
    SequenceOptions bad = o;
    bad.frames = 0;
    EXPECT_EQ(field("floor_wall", 0, bad), "frames");
    bad = o;
    bad.fps = std::nan("");
    EXPECT_EQ(field("floor_wall", 0, bad), "fps");
    bad = o;
    bad.orbit_degrees = 181.0;
    EXPECT_EQ(field("floor_wall", 0, bad), "orbit_degrees");
    bad = o;
    bad.dolly = 0.5;
    EXPECT_EQ(field("floor_wall", 0, bad), "dolly");
    bad = o;
    bad.viewport = {0, 512};
    EXPECT_EQ(field("floor_wall", 0, bad), "viewport");
}

}  // namespace
}  // namespace lixel::scene
