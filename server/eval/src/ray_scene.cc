// Building the Embree BVH of a scene's meshes (ground_truth.h): one level of every triangle, or
// two (a scene per mesh, built once, and a top level of instances over them, rebuilt per pose).
#include <lixel/eval/ground_truth.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "ray_scene_impl.h"

namespace lixel::eval {
namespace {

void OnEmbreeError(void* user, RTCError code, const char* message) {
    auto* device = static_cast<EmbreeDevice*>(user);
    device->last_error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                         (message ? message : "(no message)");
}

Result<std::shared_ptr<EmbreeDevice>> NewDevice() {
    auto device = std::make_shared<EmbreeDevice>();
    device->device = rtcNewDevice(nullptr);
    if (!device->device) {
        return Error{"embree", "rtcNewDevice failed (error " +
                                   std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) +
                                   ")"};
    }
    rtcSetDeviceErrorFunction(device->device, OnEmbreeError, device.get());
    return device;
}

Result<bool> CheckMeshes(std::span<const Mesh> meshes) {
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        const std::string field = "meshes[" + std::to_string(m) + "]";
        if (mesh.indices.size() % 3 != 0) {
            return Error{field + ".indices",
                         "size " + std::to_string(mesh.indices.size()) + " is not a multiple of 3"};
        }
        for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
            if (mesh.indices[i] >= mesh.positions.size()) {
                return Error{field + ".indices[" + std::to_string(i) + "]",
                             "vertex " + std::to_string(mesh.indices[i]) + " out of range (" +
                                 std::to_string(mesh.positions.size()) + " positions)"};
            }
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            if (!mesh.positions[i].allFinite()) {
                return Error{field + ".positions[" + std::to_string(i) + "]", "not finite"};
            }
        }
    }
    return true;
}

// A robust scene: watertight triangle tests, so no ray slips between two triangles that share an
// edge; the truth must not have the holes a rasteriser never has.
RTCScene NewScene(RTCDevice device, RTCBuildQuality quality) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, quality);
    return scene;
}

// `mesh` as geometry `id` of `scene`, its buffers' Embree copies in `vertices` and `indices`.
Result<bool> AttachMesh(RTCDevice device, RTCScene scene, unsigned id, const Mesh& mesh,
                        const std::string& last_error, const float** vertices,
                        const std::uint32_t** indices) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh.positions.size()));
    auto* idx = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), mesh.TriangleCount()));
    if (!v || !idx) {
        rtcReleaseGeometry(geometry);
        return Error{"meshes[" + std::to_string(id) + "]",
                     "Embree could not allocate buffers: " + last_error};
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        std::memcpy(v + 3 * i, mesh.positions[i].data(), 3 * sizeof(float));
    }
    std::memcpy(idx, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, id);
    rtcReleaseGeometry(geometry);
    *vertices = v;
    *indices = idx;
    return true;
}

Aabb EmptyBox() {
    return Aabb{Vec3::Constant(std::numeric_limits<double>::infinity()),
                Vec3::Constant(-std::numeric_limits<double>::infinity())};
}

void Grow(Aabb& box, const Aabb& b) {
    if (!(b.min.array() <= b.max.array()).all()) return;
    box.min = box.min.cwiseMin(b.min);
    box.max = box.max.cwiseMax(b.max);
}

// A top level over `meshes`' scenes: instance i (its geometry id) places mesh instances[i].mesh,
// `casters_only` leaving out the instances that cast no shadow.
RTCScene TopLevel(const MeshScenes& meshes, std::span<const MeshInstance> instances,
                  bool casters_only) {
    // Rebuilt every pose: a fast build over a few instances beats a careful one.
    RTCScene top = NewScene(meshes.device->device, RTC_BUILD_QUALITY_MEDIUM);
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const MeshInstance& instance = instances[i];
        if (casters_only && !instance.casts) continue;
        if (meshes.scenes[instance.mesh] == nullptr) continue;  // no triangles
        RTCGeometry geometry = rtcNewGeometry(meshes.device->device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geometry, meshes.scenes[instance.mesh]);
        float transform[12];  // RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR: four columns of three
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 3; ++r) {
                transform[3 * c + r] = static_cast<float>(instance.object_to_world(r, c));
            }
        }
        rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform);
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(top, geometry, static_cast<unsigned>(i));
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(top);
    return top;
}

}  // namespace

EmbreeDevice::~EmbreeDevice() {
    if (device) rtcReleaseDevice(device);
}

MeshScenes::~MeshScenes() {
    for (RTCScene scene : scenes) {
        if (scene) rtcReleaseScene(scene);
    }
}

RayScene::Impl::~Impl() {
    if (shadow_scene && shadow_scene != scene) rtcReleaseScene(shadow_scene);
    if (scene) rtcReleaseScene(scene);
}

RayScene::RayScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;
RayScene::~RayScene() = default;

const Aabb& RayScene::bounds() const { return impl_->bounds; }
std::int64_t RayScene::triangles() const { return impl_->triangles; }
bool RayScene::instanced() const { return impl_->meshes != nullptr; }

Result<RayScene> RayScene::Build(std::span<const Mesh> meshes) {
    if (auto ok = CheckMeshes(meshes); !ok) return ok.error();
    auto device = NewDevice();
    if (!device) return device.error();
    auto impl = std::make_unique<Impl>();
    impl->device = std::move(device).value();
    impl->scene = NewScene(impl->device->device, RTC_BUILD_QUALITY_HIGH);
    impl->shadow_scene = impl->scene;
    impl->bounds = EmptyBox();
    impl->vertices.assign(meshes.size(), nullptr);
    impl->indices.assign(meshes.size(), nullptr);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        if (mesh.TriangleCount() == 0) continue;
        if (auto ok = AttachMesh(impl->device->device, impl->scene, static_cast<unsigned>(m), mesh,
                                 impl->device->last_error, &impl->vertices[m], &impl->indices[m]);
            !ok) {
            return ok.error();
        }
        Grow(impl->bounds, mesh.Bounds());
        impl->triangles += static_cast<std::int64_t>(mesh.TriangleCount());
    }
    rtcCommitScene(impl->scene);
    if (!impl->device->last_error.empty()) return Error{"embree", impl->device->last_error};
    if (impl->triangles == 0) return Error{"meshes", "no triangles to trace"};
    return RayScene(std::move(impl));
}

Result<RayScene> RayScene::Build(std::span<const Mesh> meshes,
                                 std::span<const MeshInstance> instances) {
    if (auto ok = CheckMeshes(meshes); !ok) return ok.error();
    auto device = NewDevice();
    if (!device) return device.error();
    auto shared = std::make_shared<MeshScenes>();
    shared->device = std::move(device).value();
    shared->scenes.assign(meshes.size(), nullptr);
    shared->vertices.assign(meshes.size(), nullptr);
    shared->indices.assign(meshes.size(), nullptr);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        shared->bounds.push_back(mesh.Bounds());
        shared->triangles.push_back(static_cast<std::int64_t>(mesh.TriangleCount()));
        if (mesh.TriangleCount() == 0) continue;
        RTCScene scene = NewScene(shared->device->device, RTC_BUILD_QUALITY_HIGH);
        shared->scenes[m] = scene;
        if (auto ok = AttachMesh(shared->device->device, scene, 0, mesh, shared->device->last_error,
                                 &shared->vertices[m], &shared->indices[m]);
            !ok) {
            return Error{"meshes[" + std::to_string(m) + "]", ok.error().reason};
        }
        rtcCommitScene(scene);
    }
    if (!shared->device->last_error.empty()) return Error{"embree", shared->device->last_error};
    return Place(std::move(shared), instances);
}

Result<RayScene> RayScene::Place(std::span<const MeshInstance> instances) const {
    if (impl_->meshes == nullptr) {
        return Error{"instances", "this scene was built flat; build it with instances to place"};
    }
    return Place(impl_->meshes, instances);
}

Result<RayScene> RayScene::Place(std::shared_ptr<const MeshScenes> meshes,
                                 std::span<const MeshInstance> instances) {
    for (std::size_t i = 0; i < instances.size(); ++i) {
        if (instances[i].mesh >= meshes->scenes.size()) {
            return Error{"instances[" + std::to_string(i) + "].mesh",
                         "mesh " + std::to_string(instances[i].mesh) +
                             " >= " + std::to_string(meshes->scenes.size()) + " meshes"};
        }
        if (auto ok = CheckInstanceMatrix(instances[i].object_to_world,
                                          "instances[" + std::to_string(i) + "].object_to_world");
            !ok) {
            return ok.error();
        }
    }
    auto impl = std::make_unique<Impl>();
    impl->device = meshes->device;
    impl->meshes = meshes;
    impl->instances.assign(instances.begin(), instances.end());
    impl->bounds = EmptyBox();
    impl->scene = TopLevel(*meshes, instances, false);
    const bool all_cast = std::all_of(instances.begin(), instances.end(),
                                      [](const MeshInstance& i) { return i.casts; });
    impl->shadow_scene = all_cast ? impl->scene : TopLevel(*meshes, instances, true);
    for (const MeshInstance& instance : instances) {
        if (meshes->scenes[instance.mesh] == nullptr) continue;
        Grow(impl->bounds,
             TransformBounds(meshes->bounds[instance.mesh], instance.object_to_world));
        impl->triangles += meshes->triangles[instance.mesh];
    }
    if (!impl->device->last_error.empty()) return Error{"embree", impl->device->last_error};
    if (impl->triangles == 0) return Error{"instances", "no triangles to trace"};
    return RayScene(std::move(impl));
}

}  // namespace lixel::eval
