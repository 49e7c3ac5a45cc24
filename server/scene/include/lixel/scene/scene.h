// A complete shadow scene as every later stage sees it (DESIGN §9): meshes, the planes of
// interest in priority order, the default viewer and the light.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace lixel::scene {

// The default viewer of a scene: a perspective look-at camera and its image.
struct Camera {
    Vec3 eye = Vec3(0, 0, 5);    // world units
    Vec3 target = Vec3::Zero();  // world units, != eye
    Vec3 up = Vec3::UnitY();     // not parallel to target - eye
    double fovy_degrees = 60.0;  // vertical field of view, (0, 180)
    double near = 0.1;           // world units, > 0
    double far = 100.0;          // world units, > near
    Viewport viewport{1024, 1024};

    // Mv: world -> clip, [0, 1] clip depth (types.h).
    Mat4 Viewer() const;
    // ViewportMatrix * Mv: world -> (pixel x w, pixel y w, z w, w).
    Mat4 PixelMatrix() const;
};

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    std::vector<PlaneOfInterest> planes;  // priority order: earlier planes win shared rays
    Camera camera;
    Vec4 light = Vec4(0, 10, 0, 1);  // w = 1 point light, w = 0 direction toward the light

    // One SceneObject per mesh, pointing into `meshes`: valid while the scene is alive and its
    // mesh vector unchanged.
    std::vector<SceneObject> Objects() const;
    // Union of the meshes' bounds (an empty box, min > max, when there are no vertices).
    Aabb Bounds() const;
    std::size_t TriangleCount() const;
    // A PlanRequest for this scene's viewer, light, objects and planes with the given budget.
    PlanRequest MakePlanRequest(std::int64_t lixel_budget) const;
};

}  // namespace lixel::scene
