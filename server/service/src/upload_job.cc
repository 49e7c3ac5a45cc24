// UploadScene: an uploaded scene decoded within the upload limits into the cache.
#include "job_common.h"

#include <lixel/scene/upload.h>

#include <cstring>

namespace lixel::service {

using namespace jobs;

namespace {

// Every mesh is an object of the scene's plans: a scene no plan could hold is refused here, not
// at its first Plan.
grpc::Status CheckSceneObjects(const ServiceState& state, std::uint64_t meshes) {
    const std::uint64_t limit = PlanObjectLimit(state.options);
    if (meshes <= limit) return grpc::Status::OK;
    return Exhausted("content: " + std::to_string(meshes) + " meshes, over the " +
                     std::to_string(limit) + " objects a plan may hold (max_plan_objects)");
}

}  // namespace

grpc::Status UploadJob(ServiceState& state, const v1::SceneHeader& header,
                       const std::string& content, v1::UploadSceneResponse* response,
                       const CancelCheck& cancelled) {
    response->set_instance(state.options.instance);
    response->set_bytes(content.size());
    std::string planes;
    for (const v1::PlaneOfInterest& p : header.planes()) planes += p.SerializeAsString();
    const std::string id = ContentId(header.format(), content, planes);
    response->set_scene_id(id);
    if (auto held = state.cache.Get(id); held != nullptr) {
        response->set_already_present(true);
        std::uint64_t triangles = 0;
        for (const Mesh& m : held->scene.meshes) triangles += m.TriangleCount();
        response->set_triangles(triangles);
        return grpc::Status::OK;
    }

    Result<SceneRecord> record = Error{"content", "unread"};
    if (header.format() == v1::SCENE_FORMAT_LIXEL) {
        v1::Scene message;
        if (!message.ParseFromString(content)) {
            return InvalidArgument(Error{"content", "is not a serialized lixel.v1.Scene"});
        }
        std::uint64_t vertices = 0, triangles = 0;
        for (const v1::Mesh& m : message.meshes()) {
            vertices += static_cast<std::uint64_t>(m.positions_size()) / 3;
            triangles += static_cast<std::uint64_t>(m.indices_size()) / 3;
        }
        if (vertices > state.options.max_upload_vertices) {
            return Exhausted("content: " + std::to_string(vertices) + " vertices, over the "
                             "limit max_upload_vertices = " +
                             std::to_string(state.options.max_upload_vertices));
        }
        if (triangles > state.options.max_upload_triangles) {
            return Exhausted("content: " + std::to_string(triangles) + " triangles, over the "
                             "limit max_upload_triangles = " +
                             std::to_string(state.options.max_upload_triangles));
        }
        if (auto s = CheckSceneObjects(state, message.meshes_size()); !s.ok()) return s;
        if (cancelled && cancelled()) return CancelledStatus();
        record = DecodeScene(message, "scene");
    } else if (header.format() == v1::SCENE_FORMAT_OBJ ||
               header.format() == v1::SCENE_FORMAT_GLTF) {
        // Decoded in memory: no byte of the upload can name a file (scene/mesh_parsing.h).
        std::vector<PlaneOfInterest> plane_list;
        for (int i = 0; i < header.planes_size(); ++i) {
            auto p = DecodePlane(header.planes(i), i, "header.planes[" + std::to_string(i) + "]");
            if (!p) return InvalidArgument(p.error());
            plane_list.push_back(*p);
        }
        scene::DecodeLimits limits;
        limits.max_vertices = state.options.max_upload_vertices;
        limits.max_triangles = state.options.max_upload_triangles;
        limits.max_json_values = state.options.max_upload_json_values;
        scene::DecodeBudget budget(limits, cancelled);
        const auto format = header.format() == v1::SCENE_FORMAT_OBJ ? scene::MeshFormat::kObj
                                                                     : scene::MeshFormat::kGltf;
        auto decoded = scene::DecodeUploadedMeshes(format, content, std::move(plane_list), budget);
        if (!decoded) {
            switch (budget.outcome()) {
                case scene::DecodeOutcome::kCancelled: return CancelledStatus();
                case scene::DecodeOutcome::kOverLimit:
                    // The decoder's limit "max_vertices" is the option max_upload_vertices.
                    return Exhausted("content: max_upload_" + budget.error().field.substr(4) +
                                     ": " + budget.error().reason);
                case scene::DecodeOutcome::kInvalid: break;
            }
            return InvalidArgument(decoded.error());
        }
        record = MakeSceneRecord(std::move(*decoded));
    } else {
        return InvalidArgument(Error{"header.format", "unknown scene format " +
                                                          std::to_string(header.format())});
    }
    if (!record) return InvalidArgument(record.error());
    if (auto s = CheckSceneObjects(state, record->scene.meshes.size()); !s.ok()) return s;
    // Each placed instance's object copies its mesh's name (and so does every message about
    // it): bounded as a request's own names are.
    for (std::size_t i = 0; i < record->scene.meshes.size(); ++i) {
        const std::string& name = record->scene.meshes[i].name;
        if (name.size() > kMaxNameBytes) {
            return InvalidArgument(Error{"content: meshes[" + std::to_string(i) + "].name",
                                         "has " + std::to_string(name.size()) +
                                             " bytes: a name may take at most " +
                                             std::to_string(kMaxNameBytes)});
        }
    }
    std::uint64_t triangles = 0;
    for (const Mesh& m : record->scene.meshes) triangles += m.TriangleCount();
    response->set_triangles(triangles);
    auto shared = std::make_shared<const SceneRecord>(std::move(*record));
    if (!state.cache.Put(id, shared)) {
        return Exhausted("content: the decoded scene (" + std::to_string(shared->bytes) +
                         " bytes) is larger than the scene cache");
    }
    state.metrics.CacheBytes(static_cast<double>(state.cache.bytes()));
    return grpc::Status::OK;
}

}  // namespace lixel::service
