// The shadow volume of a whole scene for one light, built on the CPU as one VolumeMesh the GL
// pass draws as a single caster (VolumePass::Render with a GpuVolumeMesh): paper 002's smooth
// silhouettes for every closed mesh with one normal per vertex (IsSmoothCaster), and paper
// 001's robust silhouettes, sides and caps from one exact facing per triangle (ComputeFacings),
// for every other mesh: an open mesh's smooth loops are open chains, which cannot be capped.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/smooth_silhouette.h>
#include <lixel/volumes/volume_mesh.h>

#include <cstddef>
#include <span>

namespace lixel::volumes {

// Closed, with one normal per vertex.
bool IsSmoothCaster(const Mesh& mesh);

struct SceneVolumeInfo {
    int smooth_meshes = 0;  // meshes with normals: smooth silhouettes
    int robust_meshes = 0;  // the others: robust silhouettes
    std::size_t loops = 0;  // smooth silhouette loops over all meshes
    std::size_t smooth_points = 0;  // their points (SmoothStats::output_points)
};

// `adjacency[i]` = BuildEdgeAdjacency(meshes[i]). Caps::kLightAndDark closes every volume (z-fail
// needs it; z-pass ignores the caps). Errors name "meshes[i]" with ComputeSmoothSilhouette's
// reason (a mesh that cannot be oriented, a zero normal), "adjacency" when the counts differ.
Result<VolumeMesh> ExtrudeSceneVolume(std::span<const Mesh> meshes,
                                      std::span<const EdgeAdjacency> adjacency, const Vec4& light,
                                      const SmoothOptions& options,
                                      SceneVolumeInfo* info = nullptr);

// The same for placed meshes (mesh_instance.h): each instance that casts adds its mesh's volume,
// built on the mesh's own coordinates against ObjectSpaceLight (the smooth tolerances divided
// by LargestStretch, so epsilon and the normal offset hold as world distances at most) and
// carried into the world by PlaceVolume. Every orientation test is the world one up to the
// mirror's sign, which PlaceVolume turns back, so a rigid instance's volume is the volume of its
// mesh moved there. Instance meshes index `meshes` (checked by the caller); errors name
// "meshes[i]" of the instance's mesh.
Result<VolumeMesh> ExtrudeSceneVolume(std::span<const Mesh> meshes,
                                      std::span<const EdgeAdjacency> adjacency,
                                      std::span<const MeshInstance> instances, const Vec4& light,
                                      const SmoothOptions& options,
                                      SceneVolumeInfo* info = nullptr);

// The light and smooth settings an instance placed by `m` is computed with on its mesh's own
// coordinates: ObjectSpaceLight, and epsilon and normal_offset divided by LargestStretch (so
// they hold as world distances at most); the identity gives both back exactly.
struct ObjectSpace {
    Vec4 light;
    SmoothOptions options;
};
ObjectSpace InObjectSpace(const Mat4& m, const Vec4& light, const SmoothOptions& options);

// One instance's part of that volume: mesh `mesh_index` (named in errors) placed by `m`, built
// on its own coordinates and carried; counts added to `info`.
Result<VolumeMesh> ExtrudeInstanceVolume(const Mesh& mesh, std::size_t mesh_index,
                                         const EdgeAdjacency& adjacency, const Mat4& m,
                                         const Vec4& light, const SmoothOptions& options,
                                         SceneVolumeInfo* info = nullptr);

// Appends `part` to `whole`, its indices shifted past whole's vertices.
void AppendVolume(VolumeMesh& whole, const VolumeMesh& part);

// `volume`, built in an instance's object space, carried into the world by the affine `m`:
// every point p to m p (a point at infinity, w = 0, by the linear part alone, staying at
// infinity), and, when m mirrors, every triangle's winding turned, so each light cap still
// faces the light and each volume is still entered through a front face.
void PlaceVolume(VolumeMesh& volume, const Mat4& m);

}  // namespace lixel::volumes
