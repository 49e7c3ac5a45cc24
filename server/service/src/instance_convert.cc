// Instances on the wire (proto_convert.h): Instance messages against an uploaded scene's meshes.
#include <lixel/service/proto_convert.h>

#include <string>

namespace lixel::service {

Result<std::vector<MeshInstance>> DecodeInstances(
    const google::protobuf::RepeatedPtrField<v1::Instance>& instances, const SceneRecord& record,
    const std::string& field) {
    std::vector<MeshInstance> out;
    out.reserve(static_cast<std::size_t>(instances.size()));
    for (int i = 0; i < instances.size(); ++i) {
        const v1::Instance& message = instances[i];
        const std::string path = field + "[" + std::to_string(i) + "]";
        const auto found = record.mesh_index.find(message.mesh());
        if (found == record.mesh_index.end()) {
            return Error{path + ".mesh", "the scene has no mesh named '" + message.mesh() + "'"};
        }
        if (found->second == kAmbiguousMesh) {
            return Error{path + ".mesh", "the scene has more than one mesh named '" +
                                             message.mesh() + "'; name meshes apart to place them"};
        }
        MeshInstance instance;
        instance.mesh = found->second;
        if (message.has_object_to_world()) {
            auto matrix = DecodeMat4(message.object_to_world(), path + ".object_to_world");
            if (!matrix) return matrix.error();
            if (auto ok = CheckInstanceMatrix(*matrix, path + ".object_to_world"); !ok) {
                return ok.error();
            }
            instance.object_to_world = *matrix;
        }
        instance.casts = !message.has_casts() || message.casts();
        instance.receives = !message.has_receives() || message.receives();
        out.push_back(instance);
    }
    return out;
}

void EncodeInstances(const scene::Scene& scene, v1::PlanRequest* out) {
    out->clear_instances();
    for (const MeshInstance& instance : scene.instances) {
        v1::Instance* message = out->add_instances();
        message->set_mesh(scene.meshes[instance.mesh].name);
        EncodeMat4(instance.object_to_world, message->mutable_object_to_world());
        if (!instance.casts) message->set_casts(false);
        if (!instance.receives) message->set_receives(false);
    }
}

}  // namespace lixel::service
