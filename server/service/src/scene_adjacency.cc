// One adjacency per scene, built on first use (scene_adjacency.h).
#include <lixel/service/scene_adjacency.h>

#include <string>

namespace lixel::service {

Result<std::shared_ptr<const MeshAdjacency>> SceneAdjacency::Get(
    std::span<const Mesh> meshes) const {
    std::call_once(once_, [&] {
        auto built = std::make_shared<MeshAdjacency>();
        built->reserve(meshes.size());
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            auto adjacency = volumes::BuildEdgeAdjacency(meshes[i]);
            if (!adjacency) {
                error_ = Error{"meshes[" + std::to_string(i) + "]." + adjacency.error().field,
                               adjacency.error().reason};
                return;
            }
            built->push_back(std::move(adjacency).value());
        }
        adjacency_ = std::move(built);
    });
    if (error_) return *error_;
    return adjacency_;
}

std::uint64_t AdjacencyBytesBound(const Mesh& mesh) {
    return 20ull * mesh.positions.size() + 100ull * (mesh.indices.size() / 3) +
           sizeof(volumes::EdgeAdjacency);
}

}  // namespace lixel::service
