// A scene's volumes in one mesh (scene_volume.h).
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/smooth_volume.h>

#include <string>
#include <utility>
#include <vector>

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
        const std::size_t i = instance.mesh;
        const Mesh& mesh = meshes[i];
        const Mat4& m = instance.object_to_world;
        const bool in_place = m == Mat4::Identity();
        const Vec4 object_light = in_place ? light : ObjectSpaceLight(m, light);
        VolumeMesh part;
        if (IsSmoothCaster(mesh)) {
            SmoothOptions object_options = options;
            if (!in_place) {
                const double stretch = LargestStretch(m);
                object_options.epsilon /= stretch;
                object_options.normal_offset /= stretch;
            }
            auto silhouette =
                ComputeSmoothSilhouette(mesh, adjacency[i], object_light, object_options);
            if (!silhouette) {
                return Error{"meshes[" + std::to_string(i) + "]." + silhouette.error().field,
                             silhouette.error().reason};
            }
            counts.loops += silhouette->loops.size();
            ++counts.smooth_meshes;
            part = ExtrudeSmoothVolume(mesh, adjacency[i], *silhouette, object_light,
                                       Caps::kLightAndDark);
        } else {
            const auto facing = ComputeFacings(adjacency[i], object_light, Arithmetic::kExact);
            ++counts.robust_meshes;
            part = ExtrudeSilhouetteVolume(adjacency[i], facing, object_light, Caps::kLightAndDark);
        }
        if (!in_place) PlaceVolume(part, m);
        Append(volume, part);
    }
    if (info != nullptr) *info = counts;
    return volume;
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
