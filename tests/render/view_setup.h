// Shared set-ups of the view-pass tests: analytic scenes with their meshes, shapes, viewer and
// light, the maps the solver fits for them, and one call that renders a method's mask.
#pragma once

#include <lixel/render/gpu_scene.h>
#include <lixel/render/readback.h>
#include <lixel/render/renderer.h>
#include <lixel/solver/baselines.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/scheduler.h>

#include <vector>

#include "gl_environment.h"
#include "scenes.h"

namespace lixel::render::testing {

struct TestScene {
    std::vector<Mesh> meshes;
    std::vector<Shape> shapes;  // the same geometry, for TruthMask
    Mat4 viewer;
    Viewport viewport;
    Vec4 light;
    Aabb bounds;
    Vec3 origin = Vec3(0.25, 0.0, -0.5);  // camera-relative rendering is exercised
};

inline constexpr double kFloorHalf = 4.0;

// Solids only (paper 003 needs no bias for them): a floor slab with its top at y = 0 and a
// 1 x 0.04 x 1 square plate 1.2 above it; a point light above and to the side.
inline TestScene SquareOverFloor(int size) {
    TestScene s;
    const Vec3 slab_lo(-kFloorHalf, -0.5, -kFloorHalf);
    const Vec3 slab_hi(kFloorHalf, 0.0, kFloorHalf);
    const Vec3 plate_lo(-0.3, 1.18, -0.4);
    const Vec3 plate_hi(0.7, 1.22, 0.6);
    s.meshes = {BoxMesh("floor", slab_lo, slab_hi), BoxMesh("square", plate_lo, plate_hi)};
    s.shapes = {Shape::Box(slab_lo, slab_hi), Shape::Box(plate_lo, plate_hi)};
    s.viewer = Viewer(Vec3(0.0, 5.0, 5.0), Vec3(0.0, 0.0, 0.3), 45.0, 1.0);
    s.viewport = {size, size};
    s.light = Point(Vec3(1.5, 6.0, 1.0));
    s.bounds = {slab_lo, Vec3(kFloorHalf, 2.0, kFloorHalf)};
    return s;
}

// The same with open, two-sided surfaces: the floor and the square as single quads.
inline TestScene OpenSquareOverFloor(int size) {
    TestScene s = SquareOverFloor(size);
    s.meshes = {HorizontalSquare("floor", 0, 0, kFloorHalf, 0.0),
                HorizontalSquare("square", 0.2, 0.1, 0.5, 1.2)};
    s.shapes = {Shape::Rectangle(-kFloorHalf, kFloorHalf, -kFloorHalf, kFloorHalf, 0.0),
                Shape::Rectangle(-0.3, 0.7, -0.4, 0.6, 1.2)};
    return s;
}

// A closed sphere of radius 0.6 centred 1.3 above the floor slab.
inline TestScene SphereOverFloor(int size) {
    TestScene s = SquareOverFloor(size);
    s.meshes[1] = SphereMesh("sphere", Vec3(-0.2, 1.3, 0.2), 0.6, 96, 48);
    s.shapes[1] = Shape::Sphere(Vec3(-0.2, 1.3, 0.2), 0.6);
    return s;
}

// A closed box standing on the floor slab (the solids of paper 003 §3.1).
inline TestScene BoxOnSlab(int size) {
    TestScene s = SquareOverFloor(size);
    s.meshes[1] = BoxMesh("box", Vec3(-0.5, 0.0, -0.4), Vec3(0.4, 0.9, 0.5));
    s.shapes[1] = Shape::Box(Vec3(-0.5, 0.0, -0.4), Vec3(0.4, 0.9, 0.5));
    return s;
}

// The uniform baseline fitted to the extent hull with at most `budget` lixels.
inline LightMap UniformMap(const TestScene& s, std::int64_t budget) {
    auto hull = ComputeExtentHull(s.viewer, s.light, s.bounds);
    EXPECT_TRUE(hull.ok()) << hull.error().Message();
    BaselineInput input{s.viewer, s.viewport, s.light, budget, {}};
    auto fitted = FitUniformMap(input, *hull);
    EXPECT_TRUE(fitted.ok()) << fitted.error().Message();
    return fitted->map;
}

// The floor's plane-optimal map (paper 004), scaled to at most `budget` lixels.
inline LightMap FloorMap(const TestScene& s, std::int64_t budget) {
    PlaneMapRequest request;
    request.input.viewer = s.viewer;
    request.input.viewport = s.viewport;
    request.input.light = s.light;
    request.input.plane = Vec4(0, 1, 0, 0);
    const std::vector<Vec4> depth_points = BoxCorners(s.bounds);
    request.input.depth_points = depth_points;
    request.bounds = s.bounds;
    request.crop.lixel_budget = budget;
    auto map = SolvePlaneMap(request);
    EXPECT_TRUE(map.ok()) << map.error().Message();
    return map->crop.map;
}

inline PlannedMap Planned(const LightMap& map, std::vector<Pass> passes,
                          std::vector<Eigen::Vector3d> half_planes = {}) {
    PlannedMap p;
    p.map = map;
    p.name = "test map";
    p.passes = std::move(passes);
    p.lookup.half_planes = std::move(half_planes);
    p.lixels = static_cast<std::int64_t>(map.width) * map.height;
    return p;
}

struct ViewResult {
    FloatImage mask;
    std::vector<int> map_index;
    std::vector<RenderedMap> maps;
};

// Uploads the scene, renders the planned maps' passes and the view with `method`.
inline ViewResult RenderView(Renderer& renderer, const TestScene& s,
                             const std::vector<PlannedMap>& maps, ShadowMethod method,
                             const ShadowOptions& options = {}) {
    ViewResult out;
    GlContext& context = renderer.context();
    auto scene = UploadScene(context, s.meshes, s.origin);
    EXPECT_TRUE(scene.ok()) << scene.error().Message();
    if (!scene.ok()) return out;
    auto rendered = renderer.RenderMaps(*scene, maps, s.light);
    EXPECT_TRUE(rendered.ok()) << rendered.error().Message();
    if (!rendered.ok()) return out;
    auto view = renderer.RenderView(*scene, *rendered,
                                    ViewSettings{s.viewer, s.viewport, s.light, method, options});
    EXPECT_TRUE(view.ok()) << view.error().Message();
    if (!view.ok()) return out;
    auto mask = ReadMask(context, *view);
    auto index = ReadMapIndex(context, *view);
    EXPECT_TRUE(mask.ok() && index.ok());
    out.mask = std::move(mask.value());
    out.map_index = std::move(index.value());
    out.maps = std::move(rendered.value());
    return out;
}

inline ViewResult RenderView(const TestScene& s, const std::vector<PlannedMap>& maps,
                             ShadowMethod method, const ShadowOptions& options = {}) {
    return RenderView(TheRenderer(), s, maps, method, options);
}

}  // namespace lixel::render::testing
