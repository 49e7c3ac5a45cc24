// The planning scenes lixel_solver_bench plans in process and lixel_service_bench sends through
// the Plan RPC: the paper's floor/wall room seen from (0, 3, 8), lit from (4, 9, 3), with a
// number of planes of interest, or with seeded boxes standing on its floor (the room), or spread
// over 400 m x 400 m around it (an engine's world, most of it out of view).
#pragma once

#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/scheduler.h>

#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace lixel::bench {

// The room's viewer (60 degrees, square, 1024^2), light and bounds.
inline Mat4 RoomViewer() {
    return Perspective(60.0 * std::numbers::pi / 180.0, 1.0, 0.1, 100.0) *
           LookAt(Vec3(0, 3, 8), Vec3(0, 0.5, -2), Vec3::UnitY());
}
inline constexpr Viewport kRoomViewport{1024, 1024};
inline Vec4 RoomLight() { return Point(Vec3(4, 9, 3)); }
inline Aabb RoomBounds() { return Aabb{Vec3(-10, 0, -5), Vec3(10, 8, 10)}; }

// The room with `count` planes of interest: the floor, up to three walls, then table tops
// (bounded polygons) in a row, as a scene with many receivers would declare them.
inline PlanRequest RoomWithPlanes(int count) {
    PlanRequest r;
    r.viewer = RoomViewer();
    r.viewport = kRoomViewport;
    r.light = RoomLight();
    r.scene_bounds = RoomBounds();
    r.objects = {{"floor", Aabb{Vec3(-10, -0.1, -5), Vec3(10, 0, 10)}},
                 {"cube", Aabb{Vec3(-1, 0, -2), Vec3(0, 1, -1)}},
                 {"ball", Aabb{Vec3(1, 0.5, -3), Vec3(2, 1.5, -2)}}};
    const std::vector<Vec4> infinite = {Vec4(0, 1, 0, 0), Vec4(0, 0, 1, 5), Vec4(1, 0, 0, 10),
                                        Vec4(-1, 0, 0, 10)};
    for (int i = 0; i < count; ++i) {
        if (i < static_cast<int>(infinite.size())) {
            r.planes.push_back({"plane" + std::to_string(i), infinite[i], {}});
            continue;
        }
        const int k = i - static_cast<int>(infinite.size());
        const double x = -6.0 + 1.0 * (k % 12);
        const double y = 0.6 + 0.05 * k;
        r.planes.push_back(
            {"table" + std::to_string(k),
             Vec4(0, 1, 0, -y),
             {Vec3(x, y, -1), Vec3(x + 0.8, y, -1), Vec3(x + 0.8, y, -2), Vec3(x, y, -2)}});
        r.objects.push_back(
            {"table" + std::to_string(k), Aabb{Vec3(x, y - 0.05, -2), Vec3(x + 0.8, y, -1)}});
    }
    r.lixel_budget = 1024 * 1024;
    return r;
}

// Seeded boxes 5 cm to 1 m across standing on the floor, centres uniform over [x0, x1] x
// [z0, z1], added until `r` holds `count` objects. The first boxes are the same for every count,
// so the counts differ only in what is added.
inline void AddStandingBoxes(PlanRequest& r, int count, double x0, double x1, double z0,
                             double z1) {
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> x(x0, x1), z(z0, z1), side(0.05, 1.0);
    while (static_cast<int>(r.objects.size()) < count) {
        const double cx = x(rng), cz = z(rng), w = side(rng), h = side(rng), d = side(rng);
        r.objects.push_back(
            {"box" + std::to_string(r.objects.size()),
             Aabb{Vec3(cx - w / 2, 0, cz - d / 2), Vec3(cx + w / 2, h, cz + d / 2)}});
    }
}

// The room (RoomWithPlanes(2): floor and back wall) with `count` objects: its floor, cube and
// ball, then seeded boxes standing on the floor over the whole room: almost all of them lie in
// the extent hull and the casters' cones, so an index skips few of them.
inline PlanRequest RoomWithObjects(int count) {
    PlanRequest r = RoomWithPlanes(2);
    AddStandingBoxes(r, count, -9.5, 9.5, -4.5, 9.5);
    return r;
}

// An engine's world rather than a room: the same view of the room, with the scene bounds and
// the seeded boxes spread over 400 m x 400 m around it, so that most boxes lie out of view
// (behind the eye, beside the frustum, beyond the far plane) and cast nowhere near the planes'
// maps: what an object costs the plan when the scheduler can prove it does not matter.
inline PlanRequest WorldWithObjects(int count) {
    PlanRequest r = RoomWithPlanes(2);
    r.scene_bounds = Aabb{Vec3(-200, 0, -200), Vec3(200, 8, 200)};
    AddStandingBoxes(r, count, -199, 199, -199, 199);
    return r;
}

}  // namespace lixel::bench
