// Meshes uploaded once for every pass: positions relative to an origin (camera-relative
// rendering: float keeps the plane residual small, light_map.h), triangle indices, and
// triangle-adjacency indices for silhouette edges.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/gl_objects.h>
#include <lixel/render/silhouette_candidates.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace lixel::render {

// One mesh's share of the scene's buffers.
struct GpuMeshRange {
    std::string name;
    std::size_t first_index = 0;      // into the triangle index buffer
    std::size_t index_count = 0;      // 3 per triangle
    std::size_t first_adjacency = 0;  // into the adjacency index buffer
    std::size_t adjacency_count = 0;  // 6 per triangle
    // A closed solid: the second-depth pass culls its light-facing triangles; open surfaces are
    // two-sided and drawn whole (paper 003 §3.3-3.4).
    bool closed = false;
};

// One draw of a mesh as the scene's pose places it (GpuScene::Pose). Every pass draws the
// draws, not the ranges: a vertex's position relative to the origin is model * (its buffer
// position, 1), in the vertex stage (u_model).
struct GpuDraw {
    std::uint32_t range = 0;  // into GpuScene::ranges()
    // Object -> world, both relative to the origin: [A | A o + t - o] for an instance's linear
    // part A, translation t and the scene's origin o, in double, then float. The identity for a
    // mesh in place, exactly, so an unposed scene draws bit for bit as it always did.
    Mat4f model = Mat4f::Identity();
    bool mirrored = false;  // det A < 0: the passes turn the winding they call front
    bool casts = true;      // drawn into the light's maps
    bool receives = true;   // shadowed in the view
};

class GpuScene {
  public:
    const Vec3& origin() const noexcept { return origin_; }
    const std::vector<GpuMeshRange>& ranges() const noexcept { return ranges_; }
    std::size_t triangle_count() const noexcept { return triangles_; }
    int boundary_edges() const noexcept { return boundary_edges_; }
    // Vertex arrays with position at location 0 and the triangle or adjacency index buffer.
    GLuint triangles() const noexcept { return triangle_vao_.id(); }
    GLuint adjacency() const noexcept { return adjacency_vao_.id(); }
    // The position buffer (3 floats per vertex, relative to origin()) for passes that draw
    // their own index lists, and the CPU copy of the adjacency that picks them per light.
    GLuint positions() const noexcept { return positions_.id(); }
    const SilhouetteCandidates& silhouette_candidates() const noexcept { return candidates_; }
    // The draws of the current pose, in instance order; one per range, in place, until posed.
    const std::vector<GpuDraw>& draws() const noexcept { return draws_; }
    // Whether the pose is other than each mesh once in place (passes that precomputed
    // something over the buffer's positions, the silhouette candidates, use it only when not).
    bool posed() const noexcept { return posed_; }

    // Places the meshes for the passes that follow (mesh_instance.h), uploading nothing: each
    // instance's mesh index must be < ranges().size() (refused naming instances[i].mesh), its
    // matrix checked by the caller (CheckInstanceMatrix). Empty: each mesh once, in place. A
    // scene is posed by each job that draws it (one worker thread at a time holds it).
    Result<bool> Pose(std::span<const MeshInstance> instances);

  private:
    friend Result<GpuScene> UploadScene(GlContext&, std::span<const Mesh>, const Vec3&);
    Vec3 origin_ = Vec3::Zero();
    std::vector<GpuMeshRange> ranges_;
    std::size_t triangles_ = 0;
    int boundary_edges_ = 0;
    std::vector<GpuDraw> draws_;
    bool posed_ = false;
    SilhouetteCandidates candidates_;
    GlBuffer positions_;
    GlBuffer indices_;
    GlBuffer adjacency_indices_;
    GlVertexArray triangle_vao_;
    GlVertexArray adjacency_vao_;
};

// Refuses, naming the field ("meshes[2].indices[7]"): no meshes, a mesh without triangles, an
// index count not a multiple of 3, an index past the vertex count, a non-finite position, a
// non-finite origin, or more vertices than 32-bit indices address.
Result<GpuScene> UploadScene(GlContext& context, std::span<const Mesh> meshes,
                             const Vec3& origin = Vec3::Zero());

}  // namespace lixel::render
