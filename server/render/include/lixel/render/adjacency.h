// Edge adjacency for the silhouette-map pass (paper 000 §3.1 finds silhouette edges "using any of
// the techniques for shadow volumes"): GL_TRIANGLES_ADJACENCY indices built on the CPU.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace lixel::render {

inline constexpr std::uint32_t kNoNeighbour = UINT32_MAX;

struct TriangleAdjacency {
    // Six per triangle: v0, a01, v1, a12, v2, a20, where a_ij is the vertex opposite edge i-j in
    // the neighbouring triangle. At an open boundary, or past the second triangle of a
    // non-manifold edge, a_ij repeats the triangle's own opposite vertex, which the geometry
    // shader reads as "boundary".
    std::vector<std::uint32_t> indices;
    // Three per triangle: for edge k of triangle t, 3 t' + k' where triangle t' is the neighbour
    // whose vertex a_ij is, and k' its slot of the same welded edge; kNoNeighbour where a_ij
    // repeats the own opposite vertex. The silhouette culling (silhouette_candidates.h) reads the
    // neighbour's facing from it.
    std::vector<std::uint32_t> neighbours;
    int boundary_edges = 0;      // edges of one triangle
    int non_manifold_edges = 0;  // edges of three or more triangles (first two paired)
};

// Vertices with bitwise-equal positions are one vertex (meshes split vertices at seams for
// normals; the silhouette is a property of the surface, not of the vertex list).
TriangleAdjacency BuildTriangleAdjacency(std::span<const Eigen::Vector3f> positions,
                                         std::span<const std::uint32_t> indices);

}  // namespace lixel::render
