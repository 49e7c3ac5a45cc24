// Silhouettes: a scene's silhouette edges for a light, with their multiplicities.
#include <lixel/service/silhouette_encoding.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "job_common.h"

namespace lixel::service {

using namespace jobs;

grpc::Status SilhouettesJob(ServiceState& state, const v1::SilhouettesRequest& request,
                            v1::SilhouettesResponse* response, const CancelCheck& cancelled) {
    response->set_instance(state.options.instance);
    if (request.scene_id().empty()) {
        return InvalidArgument(Error{"scene_id", "is required: upload a scene first"});
    }
    const std::shared_ptr<const SceneRecord> scene = state.cache.Get(request.scene_id());
    state.metrics.CacheLookup(scene != nullptr);
    if (scene == nullptr) return NotFound(request.scene_id());
    Vec4 light = scene->scene.light;
    if (request.has_light()) {
        auto decoded = DecodeLight(request.light(), true, "light");
        if (!decoded) return InvalidArgument(decoded.error());
        light = *decoded;
    }
    // The proto's p_inf is for w scaled to 1 (or 0): the geometry is computed for that light.
    auto normalized = volumes::NormalizeLight(light);
    if (!normalized) return InvalidArgument(normalized.error());
    light = *normalized;
    auto smooth = DecodeSmoothOptions(
        request.epsilon(),
        request.has_normal_offset() ? std::optional(request.normal_offset()) : std::nullopt, "");
    if (!smooth) return InvalidArgument(smooth.error());
    auto adjacency = scene->adjacency->Get(scene->scene.meshes);
    if (!adjacency) return InvalidArgument(Error{"scene." + adjacency.error().field,
                                                 adjacency.error().reason});
    // The meshes as placed: the request's instances, or each mesh once, in place.
    std::vector<MeshInstance> placed;
    if (request.instances_size() > 0) {
        const std::uint64_t limit = PlanObjectLimit(state.options);
        if (static_cast<std::uint64_t>(request.instances_size()) > limit) {
            return Exhausted(
                "instances: " + std::to_string(request.instances_size()) +
                " instances, over the limit max_plan_objects = " + std::to_string(limit));
        }
        auto decoded = DecodeInstances(request.instances(), *scene, "instances");
        if (!decoded) return InvalidArgument(decoded.error());
        placed = std::move(decoded).value();
        if (auto s = CheckPlacedTriangles(state, *scene, placed, "instances"); !s.ok()) return s;
    } else {
        placed = IdentityInstances(scene->scene.meshes.size());
    }
    std::uint64_t bytes = 0;
    for (std::size_t k = 0; k < placed.size(); ++k) {
        const MeshInstance& instance = placed[k];
        if (!instance.casts) continue;
        const std::size_t i = instance.mesh;
        const Mesh& mesh = scene->scene.meshes[i];
        const auto index = static_cast<std::uint32_t>(i);
        const volumes::EdgeAdjacency& edges = (**adjacency)[i];
        if (cancelled && cancelled()) return CancelledStatus();  // between meshes
        // Each mesh's geometry on its own coordinates, against the light carried there.
        const Mat4& m = instance.object_to_world;
        volumes::ObjectSpace object = volumes::InObjectSpace(m, light, *smooth);
        const SilhouetteMarks marks = MarksOf(*response);
        // The meshes FILTER_SMOOTH_VOLUMES draws smooth (scene_volume.h), and only those.
        if (request.smooth() && volumes::IsSmoothCaster(mesh)) {
            // What the memory cap leaves after the meshes before, at kSmoothBytesPerPoint: no
            // epsilon sizes a silhouette past it.
            const std::uint64_t cap = state.options.memory_cap_bytes;
            object.options.max_points =
                static_cast<std::size_t>((cap - std::min(bytes, cap)) / kSmoothBytesPerPoint);
            if (object.options.max_points == 0) {
                return Exhausted("epsilon: " + SmoothOverCap(state, smooth->epsilon));
            }
            auto added = EncodeSmoothSilhouette(index, mesh, edges, object.light, object.options,
                                                request.caps(), response);
            if (!added && added.error().field == "options.max_points") {
                return Exhausted("epsilon: " + SmoothOverCap(state, smooth->epsilon));
            }
            if (!added) {
                return InvalidArgument(Error{"scene.meshes[" + std::to_string(i) + "]." +
                                                 added.error().field,
                                             added.error().reason});
            }
            bytes += *added;
        } else {
            bytes +=
                EncodeRobustSilhouette(index, mesh, edges, object.light, request.caps(), response);
        }
        PlaceSilhouettes(marks, static_cast<std::uint32_t>(k), m, response);
        if (bytes > state.options.max_response_bytes) {
            return Exhausted("silhouettes: over the " +
                             std::to_string(state.options.max_response_bytes) +
                             "-byte response limit");
        }
    }
    return grpc::Status::OK;
}

}  // namespace lixel::service
