// Scene helpers: the default camera's matrices, objects, bounds and plan requests.
#include <lixel/scene/scene.h>
#include <lixel/solver/camera.h>

#include <limits>
#include <numbers>

namespace lixel::scene {

Mat4 Camera::Viewer() const {
    const double aspect = static_cast<double>(viewport.width) / viewport.height;
    return Perspective(fovy_degrees * std::numbers::pi / 180.0, aspect, near, far) *
           LookAt(eye, target, up);
}

Mat4 Camera::PixelMatrix() const { return lixel::PixelMatrix(Viewer(), viewport); }

std::vector<SceneObject> InstanceObjects(std::span<const Mesh> meshes,
                                         std::span<const Aabb> mesh_bounds,
                                         std::span<const MeshInstance> instances) {
    std::vector<int> placed(meshes.size(), 0);
    for (const MeshInstance& instance : instances) ++placed[instance.mesh];
    std::vector<SceneObject> objects;
    objects.reserve(instances.size());
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const MeshInstance& instance = instances[i];
        if (!instance.casts && !instance.receives) continue;
        const Mesh& mesh = meshes[instance.mesh];
        SceneObject object;
        object.name = placed[instance.mesh] > 1 ? mesh.name + " #" + std::to_string(i) : mesh.name;
        object.bounds = TransformBounds(mesh_bounds[instance.mesh], instance.object_to_world);
        object.mesh = &mesh;
        object.closed = mesh.closed;
        objects.push_back(std::move(object));
    }
    return objects;
}

Aabb InstanceBounds(std::span<const Aabb> mesh_bounds, std::span<const MeshInstance> instances) {
    Aabb box{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (const MeshInstance& instance : instances) {
        const Aabb b = TransformBounds(mesh_bounds[instance.mesh], instance.object_to_world);
        if (!(b.min.array() <= b.max.array()).all()) continue;
        box.min = box.min.cwiseMin(b.min);
        box.max = box.max.cwiseMax(b.max);
    }
    return box;
}

std::vector<Aabb> Scene::MeshBounds() const {
    std::vector<Aabb> bounds;
    bounds.reserve(meshes.size());
    for (const Mesh& mesh : meshes) bounds.push_back(mesh.Bounds());
    return bounds;
}

std::vector<SceneObject> Scene::Objects() const {
    if (!instances.empty()) return InstanceObjects(meshes, MeshBounds(), instances);
    std::vector<SceneObject> objects;
    objects.reserve(meshes.size());
    for (const Mesh& mesh : meshes) {
        SceneObject object;
        object.name = mesh.name;
        object.bounds = mesh.Bounds();
        object.mesh = &mesh;
        object.closed = mesh.closed;
        objects.push_back(object);
    }
    return objects;
}

Aabb Scene::Bounds() const {
    if (!instances.empty()) return InstanceBounds(MeshBounds(), instances);
    return UnposedBounds();
}

Aabb Scene::UnposedBounds() const {
    Aabb box{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (const Mesh& mesh : meshes) {
        if (mesh.positions.empty()) continue;
        const Aabb b = mesh.Bounds();
        box.min = box.min.cwiseMin(b.min);
        box.max = box.max.cwiseMax(b.max);
    }
    return box;
}

std::size_t Scene::TriangleCount() const {
    std::size_t n = 0;
    for (const Mesh& mesh : meshes) n += mesh.TriangleCount();
    return n;
}

PlanRequest Scene::MakePlanRequest(std::int64_t lixel_budget) const {
    PlanRequest request;
    request.viewer = camera.Viewer();
    request.viewport = camera.viewport;
    request.light = light;
    request.objects = Objects();
    request.scene_bounds = Bounds();
    request.planes = planes;
    request.lixel_budget = lixel_budget;
    return request;
}

}  // namespace lixel::scene
