// Uploaded mesh files as scenes (upload.h).
#include <lixel/scene/mesh_parsing.h>
#include <lixel/scene/upload.h>
#include <lixel/solver/homogeneous.h>

namespace lixel::scene {

Result<Scene> DecodeUploadedMeshes(MeshFormat format, std::string_view content,
                                   std::vector<PlaneOfInterest> planes, DecodeBudget& budget) {
    const MeshSource source{"content", "upload", true};
    auto meshes = format == MeshFormat::kObj ? ParseObj(content, source, budget)
                                             : ParseGltf(content, source, budget);
    if (!meshes) return meshes.error();
    Scene scene;
    scene.name = "upload";
    scene.meshes = std::move(*meshes);
    scene.planes = std::move(planes);
    const Aabb b = scene.Bounds();
    scene.camera.target = b.Center();
    scene.camera.eye = b.Center() + Vec3(0.0, 0.5, 1.5) * b.Diagonal();
    scene.camera.near = 0.01 * b.Diagonal();
    scene.camera.far = 10.0 * b.Diagonal();
    scene.light = Point(b.Center() + Vec3(0.3, 1.0, 0.4) * b.Diagonal());
    return scene;
}

}  // namespace lixel::scene
