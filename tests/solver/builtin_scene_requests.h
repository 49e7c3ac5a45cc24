// The built-in scenes of server/scene/src/builtin_scenes.cc as the scheduler sees them (each
// mesh's bounds, the planes of interest, the default camera and light), rebuilt here so the
// solver's tests need no scene library: the bounds come from the same vertices, rounded to float
// as the meshes store them.
#pragma once

#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/scheduler.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace lixel::testing {

struct BuiltinSceneRequest {
    std::string name;
    PlanRequest request;
};

namespace scenes {

// Accumulates float-rounded vertices into a box, as Mesh::Bounds does.
struct Bounds {
    Aabb box{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    void Add(const Vec3& p) {
        const Vec3 f = p.cast<float>().cast<double>();
        box.min = box.min.cwiseMin(f);
        box.max = box.max.cwiseMax(f);
    }
};

inline SceneObject Object(const std::string& name, const Aabb& box, bool closed) {
    SceneObject o;
    o.name = name;
    o.bounds = box;
    o.closed = closed;
    return o;
}

inline SceneObject Quad(const std::string& name, const Vec3& corner, const Vec3& u, const Vec3& v) {
    Bounds b;
    for (const Vec3& p : {corner, Vec3(corner + u), Vec3(corner + v), Vec3(corner + u + v)}) {
        b.Add(p);
    }
    return Object(name, b.box, false);
}

inline SceneObject Box(const std::string& name, const Vec3& min, const Vec3& max) {
    Bounds b;
    b.Add(min);
    b.Add(max);
    return Object(name, b.box, true);
}

inline SceneObject Sphere(const std::string& name, const Vec3& centre, double radius, int stacks,
                          int slices) {
    Bounds b;
    b.Add(centre + Vec3(0, radius, 0));
    b.Add(centre - Vec3(0, radius, 0));
    for (int i = 1; i < stacks; ++i) {
        const double theta = std::numbers::pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            b.Add(centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                         -std::sin(theta) * std::sin(phi)));
        }
    }
    return Object(name, b.box, true);
}

inline SceneObject Torus(const std::string& name, const Vec3& centre, double major, double minor,
                         int rings, int sides) {
    Bounds b;
    for (int i = 0; i < rings; ++i) {
        const double phi = 2.0 * std::numbers::pi * i / rings;
        const Vec3 radial(std::cos(phi), 0.0, -std::sin(phi));
        for (int j = 0; j < sides; ++j) {
            const double psi = 2.0 * std::numbers::pi * j / sides;
            b.Add(centre + major * radial +
                  minor * (std::cos(psi) * radial + std::sin(psi) * Vec3::UnitY()));
        }
    }
    return Object(name, b.box, true);
}

inline SceneObject Lathe(const std::string& name, const Vec3& base,
                         const std::vector<Vec2>& profile, int slices) {
    Bounds b;
    b.Add(base + Vec3(0, profile.front().y(), 0));
    b.Add(base + Vec3(0, profile.back().y(), 0));
    for (const Vec2& r : profile) {
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            b.Add(base + r.x() * Vec3(std::cos(phi), 0.0, -std::sin(phi)) + Vec3(0, r.y(), 0));
        }
    }
    return Object(name, b.box, true);
}

inline std::vector<Vec2> PinProfile(double h) {
    return {{0.10 * h, 0.00 * h}, {0.14 * h, 0.05 * h}, {0.18 * h, 0.18 * h}, {0.19 * h, 0.28 * h},
            {0.16 * h, 0.42 * h}, {0.09 * h, 0.58 * h}, {0.07 * h, 0.66 * h}, {0.09 * h, 0.78 * h},
            {0.10 * h, 0.86 * h}, {0.08 * h, 0.95 * h}, {0.03 * h, 1.00 * h}};
}

inline SceneObject FloorQuad(double half) {
    return Quad("floor", Vec3(-half, 0, half), Vec3(2 * half, 0, 0), Vec3(0, 0, -2 * half));
}

inline PlaneOfInterest Floor() { return {"floor", Vec4(0, 1, 0, 0), {}}; }

inline Mat4 Viewer(const Vec3& eye, const Vec3& target, double fovy_degrees, double near,
                   double far, const Viewport& viewport) {
    return Perspective(fovy_degrees * std::numbers::pi / 180.0,
                       static_cast<double>(viewport.width) / viewport.height, near, far) *
           LookAt(eye, target, Vec3::UnitY());
}

// Scene::MakePlanRequest: the union of the objects' bounds as the scene bounds.
inline PlanRequest Request(std::vector<SceneObject> objects, std::vector<PlaneOfInterest> planes,
                           const Mat4& viewer, const Viewport& viewport, const Vec4& light,
                           std::int64_t budget) {
    PlanRequest r;
    r.viewer = viewer;
    r.viewport = viewport;
    r.light = light;
    r.objects = std::move(objects);
    r.scene_bounds = Aabb{Vec3::Constant(std::numeric_limits<double>::infinity()),
                          Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (const SceneObject& o : r.objects) {
        r.scene_bounds.min = r.scene_bounds.min.cwiseMin(o.bounds.min);
        r.scene_bounds.max = r.scene_bounds.max.cwiseMax(o.bounds.max);
    }
    r.planes = std::move(planes);
    r.lixel_budget = budget;
    return r;
}

}  // namespace scenes

// floor_wall at time 0, table_floor, sphere_grid (100'000 triangles), thin_plates, sphere_torus
// and pins, each with a `budget`-lixel plan request.
inline std::vector<BuiltinSceneRequest> BuiltinSceneRequests(std::int64_t budget) {
    using namespace scenes;
    const Viewport square{1024, 1024};
    std::vector<BuiltinSceneRequest> out;
    {
        auto bounce = [](double period, double apex, double phase) {
            const double s = std::fmod(0.0 / period + phase, 1.0);
            const double u = s < 0 ? s + 1.0 : s;
            return 4.0 * apex * u * (1.0 - u);
        };
        const double cube_y = bounce(1.1, 1.2, 0.35);
        std::vector<SceneObject> objects = {
            Quad("floor", Vec3(-10, 0, 10), Vec3(20, 0, 0), Vec3(0, 0, -15)),
            Quad("wall", Vec3(-10, 0, -5), Vec3(20, 0, 0), Vec3(0, 8, 0)),
            Sphere("sphere", Vec3(-2.0, 0.8 + bounce(1.3, 1.5, 0.0), -1.0), 0.8, 24, 48),
            Box("box", Vec3(0.4, cube_y, -3.1), Vec3(1.6, cube_y + 1.2, -1.9)),
            Torus("torus", Vec3(2.5, 0.25 + bounce(0.9, 1.0, 0.6), 1.5), 0.7, 0.25, 48, 24),
            Lathe("cone", Vec3(-0.5, bounce(1.7, 2.0, 0.15), 1.8), {{0.6, 0.0}, {0.0, 1.4}}, 48)};
        out.push_back(
            {"floor_wall", Request(objects, {Floor(), {"wall", Vec4(0, 0, 1, 5), {}}},
                                   Viewer(Vec3(0, 3, 8), Vec3(0, 0.5, -2), 60, 0.1, 100, square),
                                   square, Point(Vec3(4, 9, 3)), budget)});
    }
    {
        const double top = 0.8, slab = 0.04, hx = 1.0, hz = 0.6, leg = 0.05;
        std::vector<SceneObject> objects = {
            FloorQuad(6.0), Box("table top", Vec3(-hx, top - slab, -hz), Vec3(hx, top, hz))};
        int leg_index = 0;
        for (const double sx : {-1.0, 1.0}) {
            for (const double sz : {-1.0, 1.0}) {
                const Vec3 c(sx * (hx - 2 * leg), 0.0, sz * (hz - 2 * leg));
                objects.push_back(Box("leg " + std::to_string(leg_index++), c - Vec3(leg, 0, leg),
                                      c + Vec3(leg, top - slab, leg)));
            }
        }
        objects.push_back(Sphere("ball", Vec3(-0.4, top + 0.2, 0.1), 0.2, 24, 48));
        objects.push_back(Box("block", Vec3(0.3, top, -0.35), Vec3(0.6, top + 0.35, -0.05)));
        objects.push_back(Lathe("pin", Vec3(0.5, top, 0.3), PinProfile(0.45), 32));
        PlaneOfInterest table{
            "table",
            Vec4(0, 1, 0, -top),
            {Vec3(-hx, top, -hz), Vec3(-hx, top, hz), Vec3(hx, top, hz), Vec3(hx, top, -hz)}};
        out.push_back({"table_floor",
                       Request(objects, {table, Floor()},
                               Viewer(Vec3(1.6, 2.2, 3.0), Vec3(0, 0.6, 0), 50, 0.05, 50, square),
                               square, Point(Vec3(-1.5, 3.5, 1.0)), budget)});
    }
    {
        // The tessellation search of SphereGridScene for 100'000 triangles.
        const long triangles = 100'000;
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
        std::vector<SceneObject> objects = {FloorQuad(8.0)};
        for (int i = 0; i < 10; ++i) {
            for (int j = 0; j < 10; ++j) {
                objects.push_back(Sphere("sphere " + std::to_string(i) + "," + std::to_string(j),
                                         Vec3((i - 4.5) * 1.2, 0.4, (j - 4.5) * 1.2), 0.4,
                                         bands + 1, slices));
            }
        }
        out.push_back(
            {"sphere_grid", Request(objects, {Floor()},
                                    Viewer(Vec3(0, 6, 11), Vec3(0, 0, 0), 55, 0.1, 100, square),
                                    square, Point(Vec3(5, 12, -4)), budget)});
    }
    {
        std::vector<SceneObject> objects = {
            FloorQuad(6.0),
            Quad("plate low", Vec3(-2.0, 0.3, 1.0), Vec3(1.5, 0, 0), Vec3(0, 0, -1.5)),
            Quad("plate tilted", Vec3(0.0, 0.6, 1.2), Vec3(1.6, 0.5, 0), Vec3(0, 0.2, -1.6)),
            Quad("plate flipped", Vec3(-1.0, 1.2, -1.0), Vec3(0, 0, -1.4), Vec3(1.4, 0, 0)),
            Box("slab", Vec3(1.0, 0.9, -2.2), Vec3(2.4, 0.901, -0.8)),
            Box("slab stacked", Vec3(1.2, 0.902, -2.0), Vec3(2.2, 0.903, -1.0)),
            Box("slab on floor", Vec3(-2.5, 0.001, -2.5), Vec3(-1.5, 0.002, -1.5))};
        out.push_back({"thin_plates", Request(objects, {Floor()},
                                              Viewer(Vec3(0.5, 3.5, 5.0), Vec3(0, 0.3, -0.5), 55,
                                                     0.05, 60, square),
                                              square, Point(Vec3(2.0, 6.0, 2.5)), budget)});
    }
    {
        std::vector<SceneObject> objects = {
            FloorQuad(6.0), Sphere("coarse sphere", Vec3(-1.2, 1.4, 0.0), 0.9, 6, 10),
            Torus("coarse torus", Vec3(1.4, 1.2, 0.3), 0.8, 0.3, 12, 6)};
        out.push_back(
            {"sphere_torus", Request(objects, {Floor()},
                                     Viewer(Vec3(0, 3, 6), Vec3(0, 0.6, 0), 50, 0.1, 60, square),
                                     square, Direction(Vec3(0.4, 1.0, 0.3).normalized()), budget)});
    }
    {
        std::vector<SceneObject> objects = {FloorQuad(6.0)};
        int index = 0;
        for (int row = 0; row < 4; ++row) {
            for (int k = 0; k <= row; ++k) {
                const Vec3 base((k - 0.5 * row) * 0.3, 0.0, -row * 0.3 * std::sqrt(0.75));
                objects.push_back(
                    Lathe("pin " + std::to_string(index++), base, PinProfile(0.38), 40));
            }
        }
        objects.push_back(Sphere("ball", Vec3(0.1, 0.11, 0.9), 0.11, 24, 48));
        out.push_back(
            {"pins", Request(objects, {Floor()},
                             Viewer(Vec3(0.6, 0.7, 2.2), Vec3(0, 0.15, -0.4), 45, 0.02, 30, square),
                             square, Point(Vec3(-1.5, 2.5, 1.0)), budget)});
    }
    return out;
}

}  // namespace lixel::testing
