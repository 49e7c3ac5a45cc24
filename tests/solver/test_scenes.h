// Shared fixtures for the solver tests: seeded random viewer/plane/light configurations and the
// paper's floor/wall set-up.
#pragma once

#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_optimal.h>
#include <lixel/solver/types.h>

#include <cmath>
#include <numbers>
#include <random>

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

}  // namespace lixel::testing
