// Neighbour lookup per kept triangle edge.
#include <lixel/volumes/adjacency_indices.h>

namespace lixel::volumes {

std::vector<std::uint32_t> TrianglesAdjacencyIndices(const EdgeAdjacency& adjacency,
                                                     std::span<const std::uint32_t> indices) {
    std::vector<std::uint32_t> out;
    out.reserve(6 * adjacency.source.size());
    for (std::uint32_t t = 0; t < adjacency.source.size(); ++t) {
        const std::size_t first = 3 * static_cast<std::size_t>(adjacency.source[t]);
        for (int k = 0; k < 3; ++k) {
            const Edge& e = adjacency.edges[adjacency.triangle_edges[3 * t + k]];
            std::uint32_t across = indices[first + (k + 2) % 3];
            if (e.count == 2) {
                const std::uint32_t other =
                    adjacency.opposite_triangle[e.first] == t ? e.first + 1 : e.first;
                across = adjacency.representative[adjacency.opposite[other]];
            }
            out.push_back(indices[first + k]);
            out.push_back(across);
        }
    }
    return out;
}

}  // namespace lixel::volumes
