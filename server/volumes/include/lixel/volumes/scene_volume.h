// The shadow volume of a whole scene for one light, built on the CPU as one VolumeMesh the GL
// pass draws as a single caster (VolumePass::Render with a GpuVolumeMesh): paper 002's smooth
// silhouettes for every closed mesh with one normal per vertex (IsSmoothCaster), and paper
// 001's robust silhouettes, sides and caps from one exact facing per triangle (ComputeFacings),
// for every other mesh: an open mesh's smooth loops are open chains, which cannot be capped.
#pragma once

#include <lixel/solver/mesh.h>
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
};

// `adjacency[i]` = BuildEdgeAdjacency(meshes[i]). Caps::kLightAndDark closes every volume (z-fail
// needs it; z-pass ignores the caps). Errors name "meshes[i]" with ComputeSmoothSilhouette's
// reason (a mesh that cannot be oriented, a zero normal), "adjacency" when the counts differ.
Result<VolumeMesh> ExtrudeSceneVolume(std::span<const Mesh> meshes,
                                      std::span<const EdgeAdjacency> adjacency, const Vec4& light,
                                      const SmoothOptions& options,
                                      SceneVolumeInfo* info = nullptr);

}  // namespace lixel::volumes
