// The built-in scenes (builtin_scenes.h). Dimensions are in metres; the floor/wall room and its
// viewer match the solver's floor/wall fixtures and examples/floor_wall.cc.
#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/mesh_builders.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

namespace lixel::scene {
namespace {

// y = 0, lit side up.
PlaneOfInterest Floor() { return {"floor", Vec4(0.0, 1.0, 0.0, 0.0), {}}; }

// A square floor of half-width `half` centred under the origin, normal up.
Mesh FloorMesh(double half) {
    return MakeQuad("floor", Vec3(-half, 0, half), Vec3(2 * half, 0, 0), Vec3(0, 0, -2 * half));
}

// Height above the floor of a ball bouncing with period `period` and apex `apex`: a parabola
// per bounce, so the motion has a kink at each contact as a real bounce does.
double BounceHeight(double time, double period, double apex, double phase) {
    const double s = std::fmod(time / period + phase, 1.0);
    const double u = s < 0 ? s + 1.0 : s;
    return 4.0 * apex * u * (1.0 - u);
}

// A bowling-pin profile (radius, height) for a pin `height` tall.
std::vector<Vec2> PinProfile(double height) {
    const double h = height;
    return {{0.10 * h, 0.00 * h}, {0.14 * h, 0.05 * h}, {0.18 * h, 0.18 * h}, {0.19 * h, 0.28 * h},
            {0.16 * h, 0.42 * h}, {0.09 * h, 0.58 * h}, {0.07 * h, 0.66 * h}, {0.09 * h, 0.78 * h},
            {0.10 * h, 0.86 * h}, {0.08 * h, 0.95 * h}, {0.03 * h, 1.00 * h}};
}

// The profile with `per_span` points per span on the uniform Catmull-Rom curve through its
// points (end points repeated): the smooth outline they sample. 1 gives the profile itself.
std::vector<Vec2> RefinedProfile(const std::vector<Vec2>& profile, int per_span) {
    if (per_span <= 1 || profile.size() < 2) return profile;
    const auto at = [&](int i) {
        return profile[static_cast<std::size_t>(std::clamp(i, 0, int(profile.size()) - 1))];
    };
    std::vector<Vec2> out;
    for (int i = 0; i + 1 < int(profile.size()); ++i) {
        const Vec2 p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
        for (int k = 0; k < per_span; ++k) {
            const double t = double(k) / per_span, t2 = t * t, t3 = t2 * t;
            out.push_back(0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                                 (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3));
        }
    }
    out.push_back(profile.back());
    return out;
}

// The room with each shape lifted `lift[i]` above its resting height (sphere, box, torus, cone).
Scene FloorWallRoom(const std::array<double, 4>& lift) {
    Scene scene;
    scene.name = "floor_wall";
    // Floor x in [-10, 10], z in [-5, 10]; wall z = -5, x in [-10, 10], y in [0, 8].
    scene.meshes.push_back(MakeQuad("floor", Vec3(-10, 0, 10), Vec3(20, 0, 0), Vec3(0, 0, -15), 4));
    scene.meshes.push_back(MakeQuad("wall", Vec3(-10, 0, -5), Vec3(20, 0, 0), Vec3(0, 8, 0), 4));

    const double ball = 0.8;
    scene.meshes.push_back(MakeSphere("sphere", Vec3(-2.0, ball + lift[0], -1.0), ball, 24, 48));
    const double cube = 0.6;
    const double cube_y = lift[1];
    scene.meshes.push_back(MakeBox("box", Aabb{Vec3(1.0 - cube, cube_y, -2.5 - cube),
                                               Vec3(1.0 + cube, cube_y + 2 * cube, -2.5 + cube)}));
    const double tube = 0.25;
    scene.meshes.push_back(MakeTorus("torus", Vec3(2.5, tube + lift[2], 1.5), 0.7, tube, 48, 24));
    scene.meshes.push_back(
        MakeLathe("cone", Vec3(-0.5, lift[3], 1.8), {{0.6, 0.0}, {0.0, 1.4}}, 48));

    scene.planes = {Floor(), {"wall", Vec4(0.0, 0.0, 1.0, 5.0), {}}};
    scene.camera.eye = Vec3(0.0, 3.0, 8.0);
    scene.camera.target = Vec3(0.0, 0.5, -2.0);
    scene.camera.fovy_degrees = 60.0;
    scene.camera.near = 0.1;
    scene.camera.far = 100.0;
    scene.camera.viewport = {1024, 1024};
    scene.light = Point(Vec3(4.0, 9.0, 3.0));
    return scene;
}

// Each shape's bounce (period, apex, phase) at `time`: sphere, box, torus, cone.
std::array<double, 4> FloorWallLift(double time) {
    return {BounceHeight(time, 1.3, 1.5, 0.0), BounceHeight(time, 1.1, 1.2, 0.35),
            BounceHeight(time, 0.9, 1.0, 0.6), BounceHeight(time, 1.7, 2.0, 0.15)};
}

}  // namespace

Scene FloorWallScene(double time) { return FloorWallRoom(FloorWallLift(time)); }

Scene FloorWallAnimated(double time) {
    Scene scene = FloorWallRoom({0.0, 0.0, 0.0, 0.0});
    scene.instances = IdentityInstances(scene.meshes.size());
    const std::array<double, 4> lift = FloorWallLift(time);
    for (std::size_t shape = 0; shape < lift.size(); ++shape) {
        scene.instances[2 + shape].object_to_world(1, 3) = lift[shape];  // meshes 2.. are shapes
    }
    return scene;
}

Scene TableFloorScene() {
    Scene scene;
    scene.name = "table_floor";
    scene.meshes.push_back(FloorMesh(6.0));
    // Table top 2.0 x 1.2 at height 0.8 (a 4 cm slab), four legs.
    const double top = 0.8, slab = 0.04, hx = 1.0, hz = 0.6, leg = 0.05;
    scene.meshes.push_back(
        MakeBox("table top", Aabb{Vec3(-hx, top - slab, -hz), Vec3(hx, top, hz)}));
    int leg_index = 0;
    for (const double sx : {-1.0, 1.0}) {
        for (const double sz : {-1.0, 1.0}) {
            const Vec3 c(sx * (hx - 2 * leg), 0.0, sz * (hz - 2 * leg));
            scene.meshes.push_back(
                MakeBox("leg " + std::to_string(leg_index++),
                        Aabb{c - Vec3(leg, 0, leg), c + Vec3(leg, top - slab, leg)}));
        }
    }
    // Casters on the table top.
    scene.meshes.push_back(MakeSphere("ball", Vec3(-0.4, top + 0.2, 0.1), 0.2, 24, 48));
    scene.meshes.push_back(
        MakeBox("block", Aabb{Vec3(0.3, top, -0.35), Vec3(0.6, top + 0.35, -0.05)}));
    scene.meshes.push_back(MakeLathe("pin", Vec3(0.5, top, 0.3), PinProfile(0.45), 32));

    PlaneOfInterest table{"table", Vec4(0.0, 1.0, 0.0, -top), {}};
    // Counter-clockwise seen from above (+y).
    table.polygon = {Vec3(-hx, top, -hz), Vec3(-hx, top, hz), Vec3(hx, top, hz),
                     Vec3(hx, top, -hz)};
    scene.planes = {table, Floor()};
    scene.camera.eye = Vec3(1.6, 2.2, 3.0);
    scene.camera.target = Vec3(0.0, 0.6, 0.0);
    scene.camera.fovy_degrees = 50.0;
    scene.camera.near = 0.05;
    scene.camera.far = 50.0;
    scene.light = Point(Vec3(-1.5, 3.5, 1.0));
    return scene;
}

Scene SphereGridScene(long triangles) {
    triangles = std::clamp(triangles, 30'000L, 2'000'000L);
    Scene scene;
    scene.name = "sphere_grid";
    scene.meshes.push_back(FloorMesh(8.0));
    // A UV sphere with b latitude bands (b + 1 stacks) and k slices has 2 k b triangles. Search
    // b near sqrt(per / 4) (slices about twice the bands) for the (b, k) closest to the target.
    const double per_sphere = static_cast<double>(triangles - 2) / 100.0;
    const int b0 = std::max(1, static_cast<int>(std::lround(std::sqrt(per_sphere / 4.0))));
    int bands = b0;
    int slices = std::max(3, static_cast<int>(std::lround(per_sphere / (2.0 * b0))));
    double best = std::abs(2.0 * bands * slices - per_sphere);
    for (int b = std::max(1, b0 - 4); b <= b0 + 4; ++b) {
        const int k = std::max(3, static_cast<int>(std::lround(per_sphere / (2.0 * b))));
        const double miss = std::abs(2.0 * b * k - per_sphere);
        if (k >= b && k <= 4 * b && miss < best) {
            best = miss;
            bands = b;
            slices = k;
        }
    }
    const double radius = 0.4, spacing = 1.2;
    for (int i = 0; i < 10; ++i) {
        for (int j = 0; j < 10; ++j) {
            const Vec3 c((i - 4.5) * spacing, radius, (j - 4.5) * spacing);
            scene.meshes.push_back(
                MakeSphere("sphere " + std::to_string(i) + "," + std::to_string(j), c, radius,
                           bands + 1, slices));
        }
    }
    scene.planes = {Floor()};
    scene.camera.eye = Vec3(0.0, 6.0, 11.0);
    scene.camera.target = Vec3(0.0, 0.0, 0.0);
    scene.camera.fovy_degrees = 55.0;
    scene.camera.near = 0.1;
    scene.camera.far = 100.0;
    scene.light = Point(Vec3(5.0, 12.0, -4.0));
    return scene;
}

Scene ThinPlatesScene() {
    Scene scene;
    scene.name = "thin_plates";
    scene.meshes.push_back(FloorMesh(6.0));
    // Open zero-thickness plates (front face up) at several heights and tilts.
    scene.meshes.push_back(
        MakeQuad("plate low", Vec3(-2.0, 0.3, 1.0), Vec3(1.5, 0, 0), Vec3(0, 0, -1.5)));
    scene.meshes.push_back(
        MakeQuad("plate tilted", Vec3(0.0, 0.6, 1.2), Vec3(1.6, 0.5, 0), Vec3(0, 0.2, -1.6)));
    // A plate whose front faces down: seen from above, the viewer sees its back.
    scene.meshes.push_back(
        MakeQuad("plate flipped", Vec3(-1.0, 1.2, -1.0), Vec3(0, 0, -1.4), Vec3(1.4, 0, 0)));
    // Closed slabs 1 mm thick: the two depths a second-depth map separates lie 1 mm apart.
    scene.meshes.push_back(MakeBox("slab", Aabb{Vec3(1.0, 0.9, -2.2), Vec3(2.4, 0.901, -0.8)}));
    scene.meshes.push_back(
        MakeBox("slab stacked", Aabb{Vec3(1.2, 0.902, -2.0), Vec3(2.2, 0.903, -1.0)}));
    // A slab lying 1 mm above the floor: contact shadows where depth bias fails.
    scene.meshes.push_back(
        MakeBox("slab on floor", Aabb{Vec3(-2.5, 0.001, -2.5), Vec3(-1.5, 0.002, -1.5)}));
    scene.planes = {Floor()};
    scene.camera.eye = Vec3(0.5, 3.5, 5.0);
    scene.camera.target = Vec3(0.0, 0.3, -0.5);
    scene.camera.fovy_degrees = 55.0;
    scene.camera.near = 0.05;
    scene.camera.far = 60.0;
    scene.light = Point(Vec3(2.0, 6.0, 2.5));
    return scene;
}

Scene SphereTorusScene(int refinement) {
    Scene scene;
    scene.name = "sphere_torus";
    scene.meshes.push_back(FloorMesh(6.0));
    const int r = std::max(1, refinement);
    scene.meshes.push_back(MakeSphere("coarse sphere", Vec3(-1.2, 1.4, 0.0), 0.9, 6 * r, 10 * r));
    Mesh torus = MakeTorus("coarse torus", Vec3(1.4, 1.2, 0.3), 0.8, 0.3, 12 * r, 6 * r);
    scene.meshes.push_back(std::move(torus));
    scene.planes = {Floor()};
    scene.camera.eye = Vec3(0.0, 3.0, 6.0);
    scene.camera.target = Vec3(0.0, 0.6, 0.0);
    scene.camera.fovy_degrees = 50.0;
    scene.camera.near = 0.1;
    scene.camera.far = 60.0;
    scene.light = Direction(Vec3(0.4, 1.0, 0.3).normalized());
    return scene;
}

Scene PinsScene(int refinement) {
    Scene scene;
    scene.name = "pins";
    const int r = std::max(1, refinement);
    scene.meshes.push_back(FloorMesh(6.0));
    // Ten pins in the bowling triangle, 30 cm apart, 38 cm tall.
    const double spacing = 0.3;
    int index = 0;
    for (int row = 0; row < 4; ++row) {
        for (int k = 0; k <= row; ++k) {
            const Vec3 base((k - 0.5 * row) * spacing, 0.0, -row * spacing * std::sqrt(0.75));
            scene.meshes.push_back(
                MakeLathe("pin " + std::to_string(index++), base,
                          RefinedProfile(PinProfile(0.38), r), 40 * r));
        }
    }
    // A ball rolling toward them.
    scene.meshes.push_back(MakeSphere("ball", Vec3(0.1, 0.11, 0.9), 0.11, 24 * r, 48 * r));
    scene.planes = {Floor()};
    scene.camera.eye = Vec3(0.6, 0.7, 2.2);
    scene.camera.target = Vec3(0.0, 0.15, -0.4);
    scene.camera.fovy_degrees = 45.0;
    scene.camera.near = 0.02;
    scene.camera.far = 30.0;
    scene.light = Point(Vec3(-1.5, 2.5, 1.0));
    return scene;
}

Scene LongFloorScene() {
    Scene scene;
    scene.name = "long_floor";
    // 400 m along the view (z from 10 down to -390), 400 m across.
    scene.meshes.push_back(
        MakeQuad("floor", Vec3(-200, 0, 10), Vec3(400, 0, 0), Vec3(0, 0, -400), 8));
    // Posts 20 cm square and 2 m tall, alternating sides, at view distances doubling from 4 m
    // to 128 m: casters at every depth the splits and warps distribute lixels over.
    int index = 0;
    for (double distance = 4.0; distance <= 128.0; distance *= 2.0, ++index) {
        const double side = index % 2 == 0 ? -1.5 : 1.5;
        scene.meshes.push_back(MakeBox("post " + std::to_string(index),
                                       Aabb{Vec3(side - 0.1, 0.0, -distance - 0.1),
                                            Vec3(side + 0.1, 2.0, -distance + 0.1)}));
    }
    scene.planes = {Floor()};
    scene.camera.eye = Vec3(0.0, 1.7, 0.0);
    scene.camera.target = Vec3(0.0, 1.7, -10.0);  // along the floor, level
    scene.camera.fovy_degrees = 60.0;
    scene.camera.near = 0.5;
    scene.camera.far = 200.0;
    scene.camera.viewport = {1024, 1024};
    // From above and behind the viewer (+z), a little to the side.
    scene.light = Direction(Vec3(0.3, 1.0, 0.6).normalized());
    return scene;
}

std::optional<Scene> SmoothTwin(const std::string& name, int refinement) {
    if (name == "sphere_torus") return SphereTorusScene(refinement);
    if (name == "pins") return PinsScene(refinement);
    return std::nullopt;
}

std::optional<Scene> SmoothTwinOf(const Scene& scene, int refinement) {
    const std::optional<Scene> same = SmoothTwin(scene.name, 1);
    if (!same || same->meshes.size() != scene.meshes.size()) return std::nullopt;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        if (same->meshes[i].positions != scene.meshes[i].positions) return std::nullopt;
    }
    return SmoothTwin(scene.name, refinement);
}

std::vector<std::string> BuiltinSceneNames() {
    return {"floor_wall", "table_floor", "sphere_grid", "thin_plates", "sphere_torus", "pins",
            "long_floor"};
}

Result<Scene> BuiltinScene(const std::string& name) {
    if (name == "floor_wall") return FloorWallScene();
    if (name == "table_floor") return TableFloorScene();
    if (name == "sphere_grid") return SphereGridScene();
    if (name == "thin_plates") return ThinPlatesScene();
    if (name == "sphere_torus") return SphereTorusScene();
    if (name == "pins") return PinsScene();
    if (name == "long_floor") return LongFloorScene();
    std::string known;
    for (const std::string& n : BuiltinSceneNames()) known += (known.empty() ? "" : ", ") + n;
    return Error{"scene", "unknown built-in scene '" + name + "' (known: " + known + ")"};
}

}  // namespace lixel::scene
