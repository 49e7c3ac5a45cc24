// Silhouettes: a scene's silhouette edges for a light, with their multiplicities.
#include "job_common.h"

#include <lixel/service/silhouette_encoding.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/smooth_silhouette.h>

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
    std::uint64_t bytes = 0;
    for (std::size_t i = 0; i < scene->scene.meshes.size(); ++i) {
        const Mesh& mesh = scene->scene.meshes[i];
        const auto index = static_cast<std::uint32_t>(i);
        const volumes::EdgeAdjacency& edges = (**adjacency)[i];
        if (cancelled && cancelled()) return CancelledStatus();  // between meshes
        // The meshes FILTER_SMOOTH_VOLUMES draws smooth (scene_volume.h), and only those.
        if (request.smooth() && volumes::IsSmoothCaster(mesh)) {
            auto added = EncodeSmoothSilhouette(index, mesh, edges, light, *smooth,
                                                request.caps(), response);
            if (!added) {
                return InvalidArgument(Error{"scene.meshes[" + std::to_string(i) + "]." +
                                                 added.error().field,
                                             added.error().reason});
            }
            bytes += *added;
        } else {
            bytes += EncodeRobustSilhouette(index, mesh, edges, light, request.caps(), response);
        }
        if (bytes > state.options.max_response_bytes) {
            return Exhausted("silhouettes: over the " +
                             std::to_string(state.options.max_response_bytes) +
                             "-byte response limit");
        }
    }
    return grpc::Status::OK;
}

}  // namespace lixel::service
