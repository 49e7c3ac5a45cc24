// Edge adjacency of an arbitrary triangle soup (paper 001 §2.2): every undirected edge with the
// opposite vertex of each triangle that uses it. Open meshes, edges of three or more triangles
// and inconsistent winding are all ordinary input; the multiplicity (multiplicity.h) makes them
// cast correct volumes. Plain data, no GL: the GL path uploads it, clients may consume it.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace lixel::volumes {

// One undirected edge between welded points a < b (vertex_order.h), used by `count` triangles
// whose opposite points are opposite[first .. first + count).
struct Edge {
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};

struct AdjacencyStats {
    std::size_t input_triangles = 0;
    std::size_t kept_triangles = 0;
    // Skipped: two corners at one position, or three collinear corners (zero area in double).
    std::size_t degenerate_triangles = 0;
    // Skipped: the same three positions as an earlier triangle, in either winding. Kept, a
    // duplicate would double every count it takes part in.
    std::size_t duplicate_triangles = 0;
    std::size_t welded_vertices = 0;  // distinct positions
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;      // used by one triangle
    std::size_t manifold_edges = 0;      // used by two
    std::size_t non_manifold_edges = 0;  // used by three or more
    std::size_t max_opposites = 0;       // largest `count` of any edge
};

struct EdgeAdjacency {
    // Distinct input positions, sorted by Greater (vertex_order.h), so that for welded ids
    // i < j  <=>  points[i] < points[j]: every edge's a < b is the paper's A < B.
    std::vector<Eigen::Vector3f> points;
    // Input vertex -> welded id (index into points), and welded id -> the first input vertex
    // (in Greater order) at that position.
    std::vector<std::uint32_t> welded;
    std::vector<std::uint32_t> representative;
    // Kept triangles: three welded ids each, in input winding; source[t] is the input triangle
    // (index / 3) it came from, for per-corner attributes such as normals.
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint32_t> source;
    // Sorted by (a, b); independent of the input's triangle order.
    std::vector<Edge> edges;
    // Welded ids of the opposite points, per edge sorted ascending; opposite_triangle[k] is the
    // kept triangle that contributed opposite[k].
    std::vector<std::uint32_t> opposite;
    std::vector<std::uint32_t> opposite_triangle;
    // Three per kept triangle: the edge index of its corners k -> k + 1.
    std::vector<std::uint32_t> triangle_edges;
    AdjacencyStats stats;

    const Eigen::Vector3f& A(const Edge& e) const { return points[e.a]; }
    const Eigen::Vector3f& B(const Edge& e) const { return points[e.b]; }
    std::span<const std::uint32_t> Opposites(const Edge& e) const {
        return {opposite.data() + e.first, e.count};
    }
};

// Builds the adjacency; vertices with equal positions (Greater == 0, so -0 == +0) are one point.
// Errors name the field: "indices" (count not a multiple of 3), "indices[7]" (out of range),
// "positions[3]" (not finite), "positions" (more than 2^32 - 1 vertices).
Result<EdgeAdjacency> BuildEdgeAdjacency(std::span<const Eigen::Vector3f> positions,
                                         std::span<const std::uint32_t> indices);

inline Result<EdgeAdjacency> BuildEdgeAdjacency(const Mesh& mesh) {
    return BuildEdgeAdjacency(mesh.positions, mesh.indices);
}

}  // namespace lixel::volumes
