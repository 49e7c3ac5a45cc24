// The edge adjacency of an uploaded scene's meshes (paper 001 §2.2), built once, by the first
// request that needs it (Silhouettes, the volume filters' uploads), and shared by every later one
// and every GPU worker. Its memory is charged to the scene cache from the upload on
// (AdjacencyBytesBound), so building it never exceeds the cache's budget.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>
#include <lixel/volumes/edge_adjacency.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

namespace lixel::service {

using MeshAdjacency = std::vector<volumes::EdgeAdjacency>;

class SceneAdjacency {
  public:
    // One adjacency per mesh, built on the first call (concurrent first calls wait for one
    // build) and the same object on every later one; `meshes` must be the same on every call
    // (the record's). Errors name "meshes[i].<field>" and are as permanent as the scene.
    Result<std::shared_ptr<const MeshAdjacency>> Get(std::span<const Mesh> meshes) const;

  private:
    mutable std::once_flag once_;
    mutable std::shared_ptr<const MeshAdjacency> adjacency_;
    mutable std::optional<Error> error_;
};

// An upper bound on BuildEdgeAdjacency(mesh)'s memory: per vertex its point, weld and
// representative (20 bytes), per triangle its corners, source, up to three edges with their
// opposite points and triangles, and its edge slots (100 bytes).
std::uint64_t AdjacencyBytesBound(const Mesh& mesh);

}  // namespace lixel::service
