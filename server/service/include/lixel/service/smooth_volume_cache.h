// The last smooth-silhouette volume (paper 002) a scene was asked for, kept on the CPU, with each
// instance's part of it: the frames of an engine whose light and instances hold still reuse the
// whole and pay only its upload and the stencil pass; a frame that moves some instances under
// the same light rebuilds only theirs (matched by their place in the pose); a changed light or
// setting builds it all again. One entry per scene, so the memory is at most one volume of that
// scene twice (the whole and its parts; about the size of its lit caps and loops).
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/smooth_silhouette.h>
#include <lixel/volumes/volume_mesh.h>

#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

namespace lixel::service {

class SmoothVolumeCache {
  public:
    struct Lookup {
        std::shared_ptr<const volumes::VolumeMesh> volume;
        bool built = false;          // false: a hit
        double build_seconds = 0.0;  // the CPU extrusion, when built
    };

    // ExtrudeSceneVolume(meshes, adjacency, instances, light, options, ...) with Caps closed
    // (instances empty: each mesh once, in place), or the one built last for the same
    // instances, light and options (compared exactly), or that one's parts for the instances
    // whose mesh and matrix are those at the same place of the last pose. Errors are its own;
    // `built` is false only for a whole hit. `cancelled` is polled between the instances it
    // builds: true ends the build with Error{"request", "cancelled"}, keeping nothing of it.
    // options.max_points, when set, bounds the points of all the instances' silhouettes
    // together, the parts kept from the last pose included: past it the build ends with
    // Error{"options.max_points", ...} (or the instance's "meshes[i].options.max_points").
    Result<Lookup> Get(std::span<const Mesh> meshes,
                       std::span<const volumes::EdgeAdjacency> adjacency,
                       std::span<const MeshInstance> instances, const Vec4& light,
                       const volumes::SmoothOptions& options,
                       const std::function<bool()>& cancelled = {}) const;

  private:
    mutable std::mutex mutex_;
    mutable Vec4 light_ = Vec4::Zero();
    mutable std::vector<MeshInstance> instances_;  // the last pose, each mesh placed
    mutable std::vector<std::shared_ptr<const volumes::VolumeMesh>> parts_;  // null: no caster
    mutable std::vector<std::size_t> points_;  // each part's smooth-silhouette points
    mutable volumes::SmoothOptions options_;
    mutable std::shared_ptr<const volumes::VolumeMesh> volume_;
};

}  // namespace lixel::service
