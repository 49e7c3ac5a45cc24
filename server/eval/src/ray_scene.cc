// Building the Embree BVH of a scene's meshes (ground_truth.h).
#include <lixel/eval/ground_truth.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "ray_scene_impl.h"

namespace lixel::eval {
namespace {

void OnEmbreeError(void* user, RTCError code, const char* message) {
    auto* impl = static_cast<RayScene::Impl*>(user);
    impl->last_error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                       (message ? message : "(no message)");
}

}  // namespace

RayScene::Impl::~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
}

RayScene::RayScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;
RayScene::~RayScene() = default;

const Aabb& RayScene::bounds() const { return impl_->bounds; }
std::int64_t RayScene::triangles() const { return impl_->triangles; }

Result<RayScene> RayScene::Build(std::span<const Mesh> meshes) {
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

    auto impl = std::make_unique<Impl>();
    impl->device = rtcNewDevice(nullptr);
    if (!impl->device) {
        return Error{"embree", "rtcNewDevice failed (error " +
                                   std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) +
                                   ")"};
    }
    rtcSetDeviceErrorFunction(impl->device, OnEmbreeError, impl.get());
    impl->scene = rtcNewScene(impl->device);
    // Robust traversal: watertight triangle tests, so no ray slips between two triangles that
    // share an edge; the truth must not have the holes a rasteriser never has.
    rtcSetSceneFlags(impl->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_HIGH);

    impl->bounds = Aabb{Vec3::Constant(std::numeric_limits<double>::infinity()),
                        Vec3::Constant(-std::numeric_limits<double>::infinity())};
    impl->vertices.assign(meshes.size(), nullptr);
    impl->indices.assign(meshes.size(), nullptr);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        if (mesh.TriangleCount() == 0) continue;
        RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                              RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                              mesh.positions.size()));
        auto* idx = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), mesh.TriangleCount()));
        if (!v || !idx) {
            rtcReleaseGeometry(geometry);
            return Error{"meshes[" + std::to_string(m) + "]",
                         "Embree could not allocate buffers: " + impl->last_error};
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            std::memcpy(v + 3 * i, mesh.positions[i].data(), 3 * sizeof(float));
            impl->bounds.min = impl->bounds.min.cwiseMin(mesh.positions[i].cast<double>());
            impl->bounds.max = impl->bounds.max.cwiseMax(mesh.positions[i].cast<double>());
        }
        std::memcpy(idx, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(impl->scene, geometry, static_cast<unsigned>(m));
        rtcReleaseGeometry(geometry);
        impl->vertices[m] = v;
        impl->indices[m] = idx;
        impl->triangles += static_cast<std::int64_t>(mesh.TriangleCount());
    }
    rtcCommitScene(impl->scene);
    if (!impl->last_error.empty()) return Error{"embree", impl->last_error};
    if (impl->triangles == 0) return Error{"meshes", "no triangles to trace"};
    return RayScene(std::move(impl));
}

}  // namespace lixel::eval
