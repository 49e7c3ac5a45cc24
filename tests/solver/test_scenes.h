// Shared fixtures for the solver tests: seeded random viewer/plane/light configurations and the
// paper's floor/wall set-up.
#pragma once

#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_optimal.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace lixel::testing {

struct Configuration {
    Mat4 viewer;
    Viewport viewport;
    Vec4 light;
    Vec4 plane;
    Vec3 eye;
    Vec3 target;  // plane point seen at the viewport centre
    Aabb bounds;

    PlaneOptimalInput Input() const {
        PlaneOptimalInput in;
        in.viewer = viewer;
        in.viewport = viewport;
        in.light = light;
        in.plane = plane;
        return in;
    }
};

// A scene object the scheduler knows by its box only (no mesh), closed.
inline SceneObject Box(const std::string& name, const Vec3& min, const Vec3& max) {
    SceneObject o;
    o.name = name;
    o.bounds = Aabb{min, max};
    return o;
}

// The paper's room as the scheduler tests plan it: the floor and wall slabs and three boxes on
// the floor (a cube, a ball's box, a pole).
inline std::vector<SceneObject> FloorWallRoomObjects() {
    return {Box("floor", Vec3(-10, -0.1, -5), Vec3(10, 0, 10)),
            Box("wall", Vec3(-10, 0, -5.1), Vec3(10, 8, -5)),
            Box("cube", Vec3(-1, 0, -2), Vec3(0, 1, -1)),
            Box("ball", Vec3(1, 0.5, -3), Vec3(2, 1.5, -2)),
            Box("pole", Vec3(-2.5, 0, 3), Vec3(-2.2, 4, 3.3))};
}

// Where the ray origin + t direction enters `box` (slab test), for t in [0, t_max]: the entry
// parameter, 0 when the origin is inside, or infinity when the ray misses within t_max. The
// scheduler's own tracing is not reachable from tests; this is the reference they compare with.
inline double BoxEntry(const Vec3& origin, const Vec3& direction, const Aabb& box, double t_max) {
    double t0 = 0.0, t1 = t_max;
    for (int a = 0; a < 3 && t0 <= t1; ++a) {
        if (direction(a) == 0.0) {
            if (origin(a) < box.min(a) || origin(a) > box.max(a)) t0 = 2 * t1;
            continue;
        }
        double ta = (box.min(a) - origin(a)) / direction(a);
        double tb = (box.max(a) - origin(a)) / direction(a);
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

inline double Uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Vec3 RandomUnit(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    Vec3 v(n(rng), n(rng), n(rng));
    return v.normalized();
}

// A random non-degenerate configuration: a perspective viewer looking at a point of a random
// plane from 0.5 to 20 units away, the plane seen at least 5 degrees off grazing, and a point
// (or, half the time, directional) light at least 5% of the viewing distance off the plane,
// away from the viewer's centre. Planes are oriented at random (either side may face the light).
inline Configuration RandomConfiguration(std::mt19937_64& rng) {
    Configuration c;
    c.viewport.width = static_cast<int>(Uniform(rng, 16, 2048));
    c.viewport.height = static_cast<int>(Uniform(rng, 16, 2048));
    const double aspect = static_cast<double>(c.viewport.width) / c.viewport.height;
    const double fovy = Uniform(rng, 15.0, 100.0) * std::numbers::pi / 180.0;
    const double distance = Uniform(rng, 0.5, 20.0);
    c.eye = Vec3(Uniform(rng, -10, 10), Uniform(rng, -10, 10), Uniform(rng, -10, 10));
    const Vec3 forward = RandomUnit(rng);
    c.target = c.eye + distance * forward;
    Vec3 normal;
    do {
        normal = RandomUnit(rng);
    } while (std::abs(normal.dot(forward)) < std::sin(5.0 * std::numbers::pi / 180.0));
    c.plane = Vec4(normal.x(), normal.y(), normal.z(), -normal.dot(c.target));
    Vec3 up;
    do {
        up = RandomUnit(rng);
    } while (std::abs(up.dot(forward)) > 0.95);
    const double near = distance * Uniform(rng, 0.01, 0.2);
    c.viewer = Perspective(fovy, aspect, near, distance * 50.0) * LookAt(c.eye, c.target, up);
    c.bounds.min = c.target - Vec3::Constant(3.0 * distance);
    c.bounds.max = c.target + Vec3::Constant(3.0 * distance);

    if (std::bernoulli_distribution(0.5)(rng)) {
        Vec3 l;
        do {
            l = c.target + RandomUnit(rng) * Uniform(rng, 0.2, 3.0) * distance;
        } while (std::abs(normal.dot(l - c.target)) < 0.05 * distance ||
                 (l - c.eye).norm() < 0.1 * distance);
        c.light = Point(l);
    } else {
        Vec3 d;
        do {
            d = RandomUnit(rng);
        } while (std::abs(normal.dot(d)) < 0.05);
        c.light = Direction(d);
    }
    return c;
}

// Whether viewer pixel (u, v) sees the plane in front of the viewer (paper Fig. 5: the part of
// Q on this side of infinity).
inline bool SeesPlaneAt(const Mat4& pixel, const Vec4& plane, double u, double v) {
    const Vec4 x = PlanePointAtPixel(pixel, plane, u, v);
    return pixel.row(3).dot(x) * x.w() > 0.0;
}

// How many of the viewport's four corners see the plane in front of the viewer.
inline int CornersSeeingPlane(const Configuration& c) {
    const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);
    const double g = c.viewport.width;
    const double h = c.viewport.height;
    return int(SeesPlaneAt(pixel, c.plane, 0, 0)) + int(SeesPlaneAt(pixel, c.plane, g, 0)) +
           int(SeesPlaneAt(pixel, c.plane, g, h)) + int(SeesPlaneAt(pixel, c.plane, 0, h));
}

// A viewer `height` off a random plane (either orientation) whose view direction rises
// `elevation` radians away from it (negative: toward it), rolled at random, with a random
// viewport and a vertical field of view of `fovy` radians, in bounds `reach` heights around the
// eye. `target` is a point on the view axis, not on the plane.
inline Configuration ViewerOffPlane(std::mt19937_64& rng, double height, double elevation,
                                    double fovy, double reach = 30.0) {
    Configuration c;
    c.viewport.width = static_cast<int>(Uniform(rng, 16, 2048));
    c.viewport.height = static_cast<int>(Uniform(rng, 16, 2048));
    const double aspect = static_cast<double>(c.viewport.width) / c.viewport.height;
    const Vec3 normal = RandomUnit(rng);
    const Vec3 foot(Uniform(rng, -10, 10), Uniform(rng, -10, 10), Uniform(rng, -10, 10));
    c.plane = Vec4(normal.x(), normal.y(), normal.z(), -normal.dot(foot));
    if (std::bernoulli_distribution(0.5)(rng)) c.plane = -c.plane;
    c.eye = foot + height * normal;
    Vec3 along = RandomUnit(rng);
    along = (along - along.dot(normal) * normal).normalized();
    const Vec3 forward = std::cos(elevation) * along + std::sin(elevation) * normal;
    c.target = c.eye + height * forward;
    Vec3 up;
    do {
        up = RandomUnit(rng);
    } while (std::abs(up.dot(forward)) > 0.95);
    const double near = height * Uniform(rng, 0.01, 0.2);
    const double far = std::bernoulli_distribution(0.25)(rng)
                           ? std::numeric_limits<double>::infinity()
                           : near * 1e4;
    c.viewer = Perspective(fovy, aspect, near, far) * LookAt(c.eye, c.target, up);
    c.bounds.min = c.eye - Vec3::Constant(reach * height);
    c.bounds.max = c.eye + Vec3::Constant(reach * height);
    return c;
}

// A point light (half the time) or a directional one for `c`, at least `min_height` (relative
// to its distance from the eye, or as the sine of a direction's elevation) off the plane, on
// either side of it.
inline Vec4 RandomLightOffPlane(std::mt19937_64& rng, const Configuration& c, double scale,
                                double min_height) {
    const Vec3 n = c.plane.head<3>();
    const double d = c.plane.w();
    if (std::bernoulli_distribution(0.5)(rng)) {
        Vec3 l;
        do {
            l = c.eye + RandomUnit(rng) * Uniform(rng, 0.2, 20.0) * scale;
        } while (std::abs(n.dot(l) + d) < min_height * (l - c.eye).norm());
        return Point(l);
    }
    Vec3 dir;
    do {
        dir = RandomUnit(rng);
    } while (std::abs(n.dot(dir)) < min_height);
    return Direction(dir);
}

// Views whose centre ray does not meet the plane in front of the viewer (it rises away from
// the plane, meets it behind the eye, or runs along the horizon), while some of the viewport
// still shows the plane: a viewer standing on a floor and looking up. Lights at least 5% of
// their distance off the plane.
inline Configuration RandomCentreBeyondHorizonConfiguration(std::mt19937_64& rng) {
    for (;;) {
        const double fovy = Uniform(rng, 15.0, 120.0) * std::numbers::pi / 180.0;
        const double height = std::exp(Uniform(rng, std::log(0.05), std::log(20.0)));
        // Up to 1.6 half fields (about the half diagonal of a 4:3 view); a draw whose corners
        // all miss the plane is drawn again.
        const double elevation =
            std::bernoulli_distribution(0.1)(rng) ? 0.0 : Uniform(rng, 0.0, 0.5 * fovy * 1.6);
        Configuration c = ViewerOffPlane(rng, height, elevation, fovy);
        const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);
        if (SeesPlaneAt(pixel, c.plane, 0.5 * c.viewport.width, 0.5 * c.viewport.height)) {
            continue;
        }
        if (CornersSeeingPlane(c) < 1) continue;
        c.light = RandomLightOffPlane(rng, c, height, 0.05);
        return c;
    }
}

// Grazing views: a narrow vertical field of view (0.05 to 2 degrees) whose axis runs within two
// fields of the horizon, below or above it, so the plane is seen within a few degrees of
// edge-on; the bounds reach 1e5 eye heights.
inline Configuration RandomGrazingConfiguration(std::mt19937_64& rng) {
    for (;;) {
        const double fovy =
            std::exp(Uniform(rng, std::log(0.05), std::log(2.0))) * std::numbers::pi / 180.0;
        const double height = std::exp(Uniform(rng, std::log(0.05), std::log(20.0)));
        const double elevation = Uniform(rng, -2.0, 0.7) * fovy;
        Configuration c = ViewerOffPlane(rng, height, elevation, fovy, 1e5);
        if (CornersSeeingPlane(c) < 1) continue;
        c.light = RandomLightOffPlane(rng, c, height, 0.05);
        return c;
    }
}

// A random view (RandomConfiguration or, half the time, one whose centre is beyond the horizon)
// with the light moved to 1e-9 ... 1e-3 of its distance off the plane: the paper's construction
// is then close to singular (the light nearly on P), conditioning up to 1e9.
inline Configuration RandomNearDegenerateLightConfiguration(std::mt19937_64& rng) {
    Configuration c = std::bernoulli_distribution(0.5)(rng)
                          ? RandomConfiguration(rng)
                          : RandomCentreBeyondHorizonConfiguration(rng);
    const Vec3 n = c.plane.head<3>() / c.plane.head<3>().norm();
    const double d = c.plane.w() / c.plane.head<3>().norm();
    const double relative = std::pow(10.0, Uniform(rng, -9.0, -3.0));
    const double side = std::bernoulli_distribution(0.5)(rng) ? 1.0 : -1.0;
    const double scale = (c.target - c.eye).norm();
    if (std::bernoulli_distribution(0.5)(rng)) {
        // A point on the plane 0.2 to 5 view distances from the eye's foot, lifted.
        const Vec3 foot = c.eye - (n.dot(c.eye) + d) * n;
        Vec3 offset = RandomUnit(rng);
        offset = (offset - offset.dot(n) * n).normalized() * Uniform(rng, 0.2, 5.0) * scale;
        const Vec3 on_plane = foot + offset;
        const double reach = (on_plane - c.eye).norm();
        c.light = Point(on_plane + side * relative * reach * n);
    } else {
        Vec3 along = RandomUnit(rng);
        along = (along - along.dot(n) * n).normalized();
        const double s = side * relative;
        c.light = Direction(std::sqrt(1.0 - s * s) * along + s * n);
    }
    return c;
}

// The paper's floor + wall room (Chong & Gortler §3-4): floor y = 0, wall z = -5, viewer
// above the floor looking at the corner, light above and to the side. 1024 x 1024 pixels.
inline Configuration FloorWallConfiguration() {
    Configuration c;
    c.viewport = {1024, 1024};
    c.eye = Vec3(0.0, 3.0, 8.0);
    c.target = Vec3(0.0, 0.5, -2.0);
    c.viewer = Perspective(60.0 * std::numbers::pi / 180.0, 1.0, 0.1, 100.0) *
               LookAt(c.eye, c.target, Vec3::UnitY());
    c.plane = Vec4(0.0, 1.0, 0.0, 0.0);  // the floor, lit side up
    c.light = Point(Vec3(4.0, 9.0, 3.0));
    c.bounds.min = Vec3(-10.0, 0.0, -5.0);
    c.bounds.max = Vec3(10.0, 8.0, 10.0);
    return c;
}

// The paper's room as the scheduler is asked to plan it: FloorWallConfiguration's viewer and
// light, FloorWallRoomObjects, and the floor and the wall as infinite planes of interest.
inline PlanRequest FloorWallRoomRequest(std::int64_t budget) {
    const Configuration c = FloorWallConfiguration();
    PlanRequest r;
    r.viewer = c.viewer;
    r.viewport = c.viewport;
    r.light = c.light;
    r.objects = FloorWallRoomObjects();
    r.planes = {{"floor", Vec4(0, 1, 0, 0), {}}, {"wall", Vec4(0, 0, 1, 5), {}}};
    r.lixel_budget = budget;
    return r;
}

// A random room for the warps: the floor y = 0 (a flat receiver box, with up to three boxes
// standing on it), bounds 5 to 50 eye heights across; a viewer 0.3 to 5 above the floor, inside
// the bounds, looking 5 to 60 degrees below the horizon, with a near plane at 1 to 20 % of its
// height (so V starts far nearer than the floor does); a light from 15 to 90 degrees above the
// horizon, half the time a direction and otherwise a point above the bounds.
struct FloorRoom {
    Configuration c;
    std::vector<Aabb> receivers;
};

inline FloorRoom RandomFloorRoom(std::mt19937_64& rng) {
    FloorRoom room;
    Configuration& c = room.c;
    c.viewport = {static_cast<int>(Uniform(rng, 64, 2048)),
                  static_cast<int>(Uniform(rng, 64, 2048))};
    const double aspect = static_cast<double>(c.viewport.width) / c.viewport.height;
    const double fovy = Uniform(rng, 30.0, 90.0) * std::numbers::pi / 180.0;
    const double height = Uniform(rng, 0.3, 5.0);
    const double half = height * Uniform(rng, 5.0, 50.0);
    const double top = height * Uniform(rng, 2.0, 4.0);
    c.bounds = {Vec3(-half, 0.0, -half), Vec3(half, top, half)};
    c.eye = Vec3(Uniform(rng, -0.5, 0.5) * half, height, Uniform(rng, -0.5, 0.5) * half);
    const double pitch = -Uniform(rng, 5.0, 60.0) * std::numbers::pi / 180.0;
    const double yaw = Uniform(rng, 0.0, 2.0 * std::numbers::pi);
    const Vec3 forward(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                       std::cos(pitch) * std::cos(yaw));
    c.target = c.eye + forward;
    const double near = height * Uniform(rng, 0.01, 0.2);
    c.viewer = Perspective(fovy, aspect, near, 4.0 * half) * LookAt(c.eye, c.target, Vec3::UnitY());
    c.plane = Vec4(0.0, 1.0, 0.0, 0.0);
    const double elevation = Uniform(rng, 15.0, 90.0) * std::numbers::pi / 180.0;
    const double azimuth = Uniform(rng, 0.0, 2.0 * std::numbers::pi);
    const Vec3 toward(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                      std::cos(elevation) * std::cos(azimuth));
    if (std::bernoulli_distribution(0.5)(rng)) {
        c.light = Direction(toward);
    } else {
        // Above the bounds (so never inside H), at that elevation from the room's centre.
        const double lift = (top + Uniform(rng, 0.1, 2.0) * half) / toward.y();
        c.light = Point(lift * toward);
    }
    room.receivers.push_back(Aabb{Vec3(-half, 0.0, -half), Vec3(half, 0.0, half)});
    const int boxes = static_cast<int>(Uniform(rng, 0.0, 3.99));
    for (int i = 0; i < boxes; ++i) {
        const Vec3 size =
            Vec3(Uniform(rng, 0.2, 2.0), Uniform(rng, 0.2, 2.0), Uniform(rng, 0.2, 2.0)) * height;
        const Vec3 at(Uniform(rng, -0.8, 0.8) * half, 0.0, Uniform(rng, -0.8, 0.8) * half);
        room.receivers.push_back(Aabb{at - Vec3(size.x(), 0.0, size.z()), at + size});
    }
    return room;
}

}  // namespace lixel::testing
