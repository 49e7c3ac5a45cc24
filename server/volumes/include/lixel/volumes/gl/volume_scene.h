// The GPU side of robust silhouette volumes (paper 001 §2.2): per mesh its edge adjacency, and
// for the whole scene one buffer of welded points (relative to the scene's origin, as
// render::GpuScene stores positions, so caps and surfaces rasterise to identical depths), one of
// edge patches and one of kept triangles for the caps. Independent of the light: upload once,
// draw for any light.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/gl_objects.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/volume_mesh.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace lixel::volumes::gl {

struct PatchEdge {
    std::uint32_t mesh = 0;
    std::uint32_t edge = 0;  // into adjacency[mesh].edges
};

// Patches of one mesh with one size, contiguous in the patch index buffer and in patch_edges():
// each holds A, B and exactly `vertices - 2` opposite points of its edge, so no patch is padded
// to another edge's fan (issue 16.6).
struct PatchGroup {
    std::uint32_t mesh = 0;
    int vertices = 0;             // GL_PATCH_VERTICES for the group, >= 3
    std::size_t first_patch = 0;  // into patch_edges()
    std::size_t patches = 0;
};

// A mesh's kept triangles in the cap index buffer, for its z-fail caps.
struct CapRange {
    std::size_t first_triangle = 0;
    std::size_t triangles = 0;
};

class VolumeScene {
  public:
    const Vec3& origin() const noexcept { return origin_; }
    const std::vector<EdgeAdjacency>& adjacency() const noexcept { return *adjacency_; }
    // The largest patch of any group (A, B and up to patch_vertices() - 2 opposite points); 0
    // when the scene has no edges.
    int patch_vertices() const noexcept { return patch_vertices_; }
    std::size_t patch_count() const noexcept { return patch_edges_.size(); }
    // Ordered by mesh, then size; their patches cover patch_edges() in order.
    const std::vector<PatchGroup>& patch_groups() const noexcept { return patch_groups_; }
    // One per mesh.
    const std::vector<CapRange>& cap_ranges() const noexcept { return cap_ranges_; }
    // Which edge each patch draws; an edge with more opposite points than a patch holds is split
    // over several patches, whose multiplicities add up.
    const std::vector<PatchEdge>& patch_edges() const noexcept { return patch_edges_; }
    std::size_t split_edges() const noexcept { return split_edges_; }
    // Indices in the patch buffer: sum over patches of their size.
    std::size_t patch_index_count() const noexcept { return patch_index_count_; }
    std::size_t cap_triangles() const noexcept { return cap_triangles_; }
    GLuint patches() const noexcept { return patch_vao_.id(); }  // position at location 0
    GLuint caps() const noexcept { return cap_vao_.id(); }

  private:
    friend Result<VolumeScene> UploadVolumeScene(
        render::GlContext&, std::shared_ptr<const std::vector<EdgeAdjacency>>, const Vec3&, int);
    Vec3 origin_ = Vec3::Zero();
    std::shared_ptr<const std::vector<EdgeAdjacency>> adjacency_;
    int patch_vertices_ = 0;
    std::vector<PatchEdge> patch_edges_;
    std::vector<PatchGroup> patch_groups_;
    std::vector<CapRange> cap_ranges_;
    std::size_t split_edges_ = 0;
    std::size_t patch_index_count_ = 0;
    std::size_t cap_triangles_ = 0;
    render::GlBuffer points_;
    render::GlBuffer patch_indices_;
    render::GlBuffer cap_indices_;
    render::GlVertexArray patch_vao_;
    render::GlVertexArray cap_vao_;
};

// Builds every mesh's adjacency and uploads it. `max_opposites` per patch defaults (0) to what
// the context allows: min(GL_MAX_PATCH_VERTICES - 2, (GL_MAX_TESS_GEN_LEVEL + 1) / 2), 30 on
// llvmpipe (32 patch vertices, level 64), so 2|m| - 1 never exceeds the tessellation limit.
// Errors name the field: "meshes" (none), "meshes[2].indices[7]", "origin", "max_opposites".
Result<VolumeScene> UploadVolumeScene(render::GlContext& context, std::span<const Mesh> meshes,
                                      const Vec3& origin = Vec3::Zero(), int max_opposites = 0);

// The same from adjacency built before (one per mesh, BuildEdgeAdjacency's), which the scene
// shares instead of building its own: the service builds it once per scene for every worker.
// Errors: "adjacency" (null or empty), "origin", "max_opposites".
Result<VolumeScene> UploadVolumeScene(render::GlContext& context,
                                      std::shared_ptr<const std::vector<EdgeAdjacency>> adjacency,
                                      const Vec3& origin = Vec3::Zero(), int max_opposites = 0);

// A volume built on the CPU (smooth silhouettes, or any VolumeMesh), uploaded for drawing:
// homogeneous points relative to the origin, sides and caps as separate index ranges.
class GpuVolumeMesh {
  public:
    std::size_t side_indices() const noexcept { return sides_; }
    std::size_t cap_indices() const noexcept { return caps_; }
    GLuint vertex_array() const noexcept { return vao_.id(); }  // vec4 position at location 0
    // The finite triangles (light caps and gap strips) for the z-pass test, world coordinates.
    const VolumeMesh& source() const noexcept { return source_; }

  private:
    friend Result<GpuVolumeMesh> UploadVolumeMesh(render::GlContext&, const VolumeMesh&,
                                                  const Vec3&);
    std::size_t sides_ = 0;
    std::size_t caps_ = 0;
    VolumeMesh source_;
    render::GlBuffer vertices_;
    render::GlBuffer indices_;
    render::GlVertexArray vao_;
};

Result<GpuVolumeMesh> UploadVolumeMesh(render::GlContext& context, const VolumeMesh& volume,
                                       const Vec3& origin = Vec3::Zero());

}  // namespace lixel::volumes::gl
