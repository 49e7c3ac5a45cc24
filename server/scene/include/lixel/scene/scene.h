// A complete shadow scene as every later stage sees it (DESIGN §9): meshes, the planes of
// interest in priority order, the default viewer and the light.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <cstddef>
#include <span>
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
    // This frame's pose (mesh_instance.h): the meshes placed by instances, each valid
    // (CheckInstanceMatrix, mesh < meshes.size()). Empty: each mesh once, in place.
    std::vector<MeshInstance> instances;

    // One SceneObject per mesh, or per instance that casts or receives when `instances` is set,
    // pointing into `meshes`: valid while the scene is alive and its mesh vector unchanged.
    std::vector<SceneObject> Objects() const;
    // Union of the meshes' bounds, or of the instances' (an empty box, min > max, when there are
    // no vertices).
    Aabb Bounds() const;
    // Each mesh's own bounds, in its object coordinates.
    std::vector<Aabb> MeshBounds() const;
    // Union of the meshes' bounds as uploaded, whatever the pose: what the GPU scene's origin
    // (its centre) comes from, on the server and in a client drawing the same meshes.
    Aabb UnposedBounds() const;
    std::size_t TriangleCount() const;
    // A PlanRequest for this scene's viewer, light, objects and planes with the given budget.
    PlanRequest MakePlanRequest(std::int64_t lixel_budget) const;
};

// The scheduler's objects of a posed scene: one per instance that casts or receives (one that
// does neither changes no shadow), its bounds the mesh's carried by the instance
// (TransformBounds), named for the mesh, with " #i" (the instance's index) when the mesh is
// placed more than once. Casting only or receiving only counts as both: the plan covers more
// than it must, never less. `mesh_bounds[m]` is meshes[m].Bounds(), computed once per scene.
std::vector<SceneObject> InstanceObjects(std::span<const Mesh> meshes,
                                         std::span<const Aabb> mesh_bounds,
                                         std::span<const MeshInstance> instances);
// Union of the instances' bounds, every instance counted (the view sees non-casters too).
Aabb InstanceBounds(std::span<const Aabb> mesh_bounds, std::span<const MeshInstance> instances);

}  // namespace lixel::scene
