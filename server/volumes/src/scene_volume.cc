// A scene's volumes in one mesh (scene_volume.h).
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/smooth_volume.h>

#include <string>
#include <utility>
#include <vector>

namespace lixel::volumes {

void AppendVolume(VolumeMesh& whole, const VolumeMesh& part) {
    const auto offset = static_cast<std::uint32_t>(whole.vertices.size());
    whole.vertices.insert(whole.vertices.end(), part.vertices.begin(), part.vertices.end());
    for (const std::uint32_t i : part.sides) whole.sides.push_back(i + offset);
    for (const std::uint32_t i : part.caps) whole.caps.push_back(i + offset);
}

bool IsSmoothCaster(const Mesh& mesh) {
    return mesh.closed && !mesh.normals.empty() && mesh.normals.size() == mesh.positions.size();
}

Result<VolumeMesh> ExtrudeSceneVolume(std::span<const Mesh> meshes,
                                      std::span<const EdgeAdjacency> adjacency, const Vec4& light,
                                      const SmoothOptions& options, SceneVolumeInfo* info) {
    // Each mesh once in place: object space is the world, and the identity carries the light,
    // the tolerances and every point exactly.
    const std::vector<MeshInstance> in_place = IdentityInstances(meshes.size());
    return ExtrudeSceneVolume(meshes, adjacency, in_place, light, options, info);
}

Result<VolumeMesh> ExtrudeSceneVolume(std::span<const Mesh> meshes,
                                      std::span<const EdgeAdjacency> adjacency,
                                      std::span<const MeshInstance> instances, const Vec4& light,
                                      const SmoothOptions& options, SceneVolumeInfo* info) {
    if (adjacency.size() != meshes.size()) {
        return Error{"adjacency", "one per mesh: " + std::to_string(adjacency.size()) + " for " +
                                      std::to_string(meshes.size()) + " meshes"};
    }
    SceneVolumeInfo counts;
    VolumeMesh volume;
    for (const MeshInstance& instance : instances) {
        if (!instance.casts) continue;
        auto part =
            ExtrudeInstanceVolume(meshes[instance.mesh], instance.mesh, adjacency[instance.mesh],
                                  instance.object_to_world, light, options, &counts);
        if (!part) return part.error();
        AppendVolume(volume, *part);
    }
    if (info != nullptr) *info = counts;
    return volume;
}

ObjectSpace InObjectSpace(const Mat4& m, const Vec4& light, const SmoothOptions& options) {
    ObjectSpace out{light, options};
    if (m == Mat4::Identity()) return out;
    out.light = ObjectSpaceLight(m, light);
    const double stretch = LargestStretch(m);
    out.options.epsilon /= stretch;
    out.options.normal_offset /= stretch;
    return out;
}

Result<VolumeMesh> ExtrudeInstanceVolume(const Mesh& mesh, std::size_t mesh_index,
                                         const EdgeAdjacency& adjacency, const Mat4& m,
                                         const Vec4& light, const SmoothOptions& options,
                                         SceneVolumeInfo* info) {
    const bool in_place = m == Mat4::Identity();
    const ObjectSpace object = InObjectSpace(m, light, options);
    const Vec4& object_light = object.light;
    VolumeMesh part;
    if (IsSmoothCaster(mesh)) {
        auto silhouette = ComputeSmoothSilhouette(mesh, adjacency, object_light, object.options);
        if (!silhouette) {
            return Error{"meshes[" + std::to_string(mesh_index) + "]." + silhouette.error().field,
                         silhouette.error().reason};
        }
        if (info != nullptr) {
            info->loops += silhouette->loops.size();
            info->smooth_points += silhouette->stats.output_points;
            ++info->smooth_meshes;
        }
        part = ExtrudeSmoothVolume(mesh, adjacency, *silhouette, object_light, Caps::kLightAndDark);
    } else {
        const auto facing = ComputeFacings(adjacency, object_light, Arithmetic::kExact);
        if (info != nullptr) ++info->robust_meshes;
        part = ExtrudeSilhouetteVolume(adjacency, facing, object_light, Caps::kLightAndDark);
    }
    if (!in_place) PlaceVolume(part, m);
    return part;
}

void PlaceVolume(VolumeMesh& volume, const Mat4& m) {
    for (Eigen::Vector4d& v : volume.vertices) v = m * v;  // m's last row keeps w
    if (!Mirrors(m)) return;
    for (std::vector<std::uint32_t>* triangles : {&volume.sides, &volume.caps}) {
        for (std::size_t t = 0; t + 2 < triangles->size(); t += 3) {
            std::swap((*triangles)[t + 1], (*triangles)[t + 2]);
        }
    }
}

}  // namespace lixel::volumes
