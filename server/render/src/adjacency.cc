// Edge adjacency by welded position.
#include <lixel/render/adjacency.h>

#include <array>
#include <cstring>
#include <unordered_map>

namespace lixel::render {
namespace {

struct PositionKey {
    std::array<std::uint32_t, 3> bits;
    bool operator==(const PositionKey&) const = default;
};

struct PositionHash {
    std::size_t operator()(const PositionKey& k) const noexcept {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
        return static_cast<std::size_t>(h);
    }
};

PositionKey KeyOf(const Eigen::Vector3f& p) {
    PositionKey k;
    for (int i = 0; i < 3; ++i) {
        float v = p[i] == 0.0f ? 0.0f : p[i];  // -0 and +0 are one position
        std::memcpy(&k.bits[static_cast<std::size_t>(i)], &v, sizeof(float));
    }
    return k;
}

}  // namespace

TriangleAdjacency BuildTriangleAdjacency(std::span<const Eigen::Vector3f> positions,
                                         std::span<const std::uint32_t> indices) {
    std::vector<std::uint32_t> canonical(positions.size());
    {
        std::unordered_map<PositionKey, std::uint32_t, PositionHash> first;
        first.reserve(positions.size());
        for (std::size_t i = 0; i < positions.size(); ++i) {
            canonical[i] =
                first.try_emplace(KeyOf(positions[i]), static_cast<std::uint32_t>(i)).first->second;
        }
    }
    const std::size_t triangles = indices.size() / 3;
    // Undirected welded edge -> up to two (triangle, slot) users; slot k is edge k -> k + 1.
    struct Users {
        std::uint32_t first = UINT32_MAX;
        std::uint32_t second = UINT32_MAX;
        int count = 0;
    };
    std::unordered_map<std::uint64_t, Users> edges;
    edges.reserve(triangles * 2);
    auto edge_key = [&](std::uint32_t a, std::uint32_t b) {
        std::uint64_t ca = canonical[a];
        std::uint64_t cb = canonical[b];
        if (ca > cb) std::swap(ca, cb);
        return (ca << 32) | cb;
    };
    for (std::size_t t = 0; t < triangles; ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            Users& u = edges[edge_key(indices[3 * t + k], indices[3 * t + (k + 1) % 3])];
            const auto user = static_cast<std::uint32_t>(3 * t + k);
            if (u.count == 0) u.first = user;
            if (u.count == 1) u.second = user;
            ++u.count;
        }
    }
    TriangleAdjacency out;
    out.indices.resize(6 * triangles);
    out.neighbours.assign(3 * triangles, kNoNeighbour);
    for (std::size_t t = 0; t < triangles; ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t a = indices[3 * t + k];
            const std::uint32_t b = indices[3 * t + (k + 1) % 3];
            const std::uint32_t own_opposite = indices[3 * t + (k + 2) % 3];
            const Users& u = edges.at(edge_key(a, b));
            const auto self = static_cast<std::uint32_t>(3 * t + k);
            std::uint32_t across = own_opposite;
            if (u.count >= 2 && (u.first == self || u.second == self)) {
                const std::uint32_t other = u.first == self ? u.second : u.first;
                const std::uint32_t other_triangle = other / 3;
                across = indices[3 * other_triangle + (other % 3 + 2) % 3];
                out.neighbours[3 * t + k] = other;
            }
            out.indices[6 * t + 2 * k] = a;
            out.indices[6 * t + 2 * k + 1] = across;
        }
    }
    for (const auto& [key, u] : edges) {
        if (u.count == 1) ++out.boundary_edges;
        if (u.count > 2) ++out.non_manifold_edges;
    }
    return out;
}

}  // namespace lixel::render
