// A scene's volumes in one mesh (scene_volume.h).
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/smooth_volume.h>

#include <string>

namespace lixel::volumes {

namespace {

// Appends `part` to `whole`, its indices shifted past whole's vertices.
void Append(VolumeMesh& whole, const VolumeMesh& part) {
    const auto offset = static_cast<std::uint32_t>(whole.vertices.size());
    whole.vertices.insert(whole.vertices.end(), part.vertices.begin(), part.vertices.end());
    for (const std::uint32_t i : part.sides) whole.sides.push_back(i + offset);
    for (const std::uint32_t i : part.caps) whole.caps.push_back(i + offset);
}

}  // namespace

bool IsSmoothCaster(const Mesh& mesh) {
    return mesh.closed && !mesh.normals.empty() && mesh.normals.size() == mesh.positions.size();
}

Result<VolumeMesh> ExtrudeSceneVolume(std::span<const Mesh> meshes,
                                      std::span<const EdgeAdjacency> adjacency, const Vec4& light,
                                      const SmoothOptions& options, SceneVolumeInfo* info) {
    if (adjacency.size() != meshes.size()) {
        return Error{"adjacency", "one per mesh: " + std::to_string(adjacency.size()) + " for " +
                                      std::to_string(meshes.size()) + " meshes"};
    }
    SceneVolumeInfo counts;
    VolumeMesh volume;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const Mesh& mesh = meshes[i];
        if (IsSmoothCaster(mesh)) {
            auto silhouette = ComputeSmoothSilhouette(mesh, adjacency[i], light, options);
            if (!silhouette) {
                return Error{"meshes[" + std::to_string(i) + "]." + silhouette.error().field,
                             silhouette.error().reason};
            }
            counts.loops += silhouette->loops.size();
            ++counts.smooth_meshes;
            Append(volume, ExtrudeSmoothVolume(mesh, adjacency[i], *silhouette, light,
                                               Caps::kLightAndDark));
        } else {
            const auto facing = ComputeFacings(adjacency[i], light, Arithmetic::kExact);
            ++counts.robust_meshes;
            Append(volume, ExtrudeSilhouetteVolume(adjacency[i], facing, light,
                                                   Caps::kLightAndDark));
        }
    }
    if (info != nullptr) *info = counts;
    return volume;
}

}  // namespace lixel::volumes
