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

std::vector<SceneObject> Scene::Objects() const {
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
