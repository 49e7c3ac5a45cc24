// GL_TRIANGLES_ADJACENCY indices from an EdgeAdjacency, for geometry-shader silhouette passes
// (the renderer's silhouette map, paper 000 §3.1) that want the neighbour across each edge.
#pragma once

#include <lixel/volumes/edge_adjacency.h>

#include <cstdint>
#include <span>
#include <vector>

namespace lixel::volumes {

// Six input-vertex indices per kept triangle (adjacency.source order): v0, a01, v1, a12, v2,
// a20, where a_ij is the vertex opposite edge i-j in the other triangle of a two-triangle edge.
// Open edges (one triangle) and non-manifold edges (three or more) repeat the triangle's own
// opposite vertex, which a geometry shader reads as "no single neighbour: always an outline".
// `indices` are the ones the adjacency was built from.
std::vector<std::uint32_t> TrianglesAdjacencyIndices(const EdgeAdjacency& adjacency,
                                                     std::span<const std::uint32_t> indices);

}  // namespace lixel::volumes
