// Edge adjacency by sorting, not hashing: welding, duplicate detection and edge grouping are each
// one sort, so the result (and its order) depends only on the set of triangles.
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/vertex_order.h>

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <string>

namespace lixel::volumes {
namespace {

Result<bool> Validate(std::span<const Eigen::Vector3f> positions,
                      std::span<const std::uint32_t> indices) {
    if (indices.size() % 3 != 0) {
        return Error{"indices", std::to_string(indices.size()) + " indices, not a multiple of 3"};
    }
    if (positions.size() >= std::numeric_limits<std::uint32_t>::max()) {
        return Error{"positions", "more than 2^32 - 1 vertices"};
    }
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!positions[i].allFinite()) {
            return Error{"positions[" + std::to_string(i) + "]", "not finite"};
        }
    }
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] >= positions.size()) {
            return Error{"indices[" + std::to_string(i) + "]",
                         "index " + std::to_string(indices[i]) +
                             " >= " + std::to_string(positions.size()) + " vertices"};
        }
    }
    return true;
}

// Welds equal positions and numbers the points in Greater order.
void Weld(std::span<const Eigen::Vector3f> positions, EdgeAdjacency& out) {
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t i, std::uint32_t j) {
        return Greater(positions[i], positions[j]) < 0;
    });
    out.welded.assign(positions.size(), 0);
    out.points.clear();
    out.representative.clear();
    for (std::size_t k = 0; k < order.size(); ++k) {
        const Eigen::Vector3f& p = positions[order[k]];
        if (out.points.empty() || Greater(out.points.back(), p) != 0) {
            out.points.push_back(p);
            out.representative.push_back(order[k]);
        }
        out.welded[order[k]] = static_cast<std::uint32_t>(out.points.size() - 1);
    }
}

bool Collinear(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
    const Eigen::Vector3d u = (b - a).cast<double>();
    const Eigen::Vector3d v = (c - a).cast<double>();
    return u.cross(v).squaredNorm() == 0.0;
}

struct EdgeUse {
    std::uint64_t key;      // a << 32 | b, a < b
    std::uint64_t payload;  // opposite welded id << 32 | slot (3 * kept triangle + corner k)

    bool operator<(const EdgeUse& o) const {
        return key != o.key ? key < o.key : payload < o.payload;
    }
};

}  // namespace

Result<EdgeAdjacency> BuildEdgeAdjacency(std::span<const Eigen::Vector3f> positions,
                                         std::span<const std::uint32_t> indices) {
    if (auto ok = Validate(positions, indices); !ok) return ok.error();
    EdgeAdjacency out;
    AdjacencyStats& stats = out.stats;
    stats.input_triangles = indices.size() / 3;
    Weld(positions, out);
    stats.welded_vertices = out.points.size();

    // Candidate triangles: welded corners, degenerate ones dropped.
    std::vector<std::array<std::uint32_t, 3>> corners;
    std::vector<std::uint32_t> sources;
    corners.reserve(stats.input_triangles);
    sources.reserve(stats.input_triangles);
    for (std::size_t t = 0; t < stats.input_triangles; ++t) {
        const std::array<std::uint32_t, 3> w = {out.welded[indices[3 * t]],
                                                out.welded[indices[3 * t + 1]],
                                                out.welded[indices[3 * t + 2]]};
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0] ||
            Collinear(out.points[w[0]], out.points[w[1]], out.points[w[2]])) {
            ++stats.degenerate_triangles;
            continue;
        }
        corners.push_back(w);
        sources.push_back(static_cast<std::uint32_t>(t));
    }

    // Duplicates: equal sorted corner sets; the earliest input triangle is kept.
    std::vector<std::array<std::uint32_t, 4>> by_set(corners.size());
    for (std::size_t i = 0; i < corners.size(); ++i) {
        std::array<std::uint32_t, 3> c = corners[i];
        std::sort(c.begin(), c.end());
        by_set[i] = {c[0], c[1], c[2], static_cast<std::uint32_t>(i)};
    }
    std::sort(by_set.begin(), by_set.end());
    std::vector<char> keep(corners.size(), 1);
    for (std::size_t k = 1; k < by_set.size(); ++k) {
        if (by_set[k][0] == by_set[k - 1][0] && by_set[k][1] == by_set[k - 1][1] &&
            by_set[k][2] == by_set[k - 1][2]) {
            keep[by_set[k][3]] = 0;
            ++stats.duplicate_triangles;
        }
    }
    for (std::size_t i = 0; i < corners.size(); ++i) {
        if (!keep[i]) continue;
        out.triangles.insert(out.triangles.end(), corners[i].begin(), corners[i].end());
        out.source.push_back(sources[i]);
    }
    stats.kept_triangles = out.source.size();

    // Edge uses, grouped by one sort; opposites ascending within an edge.
    std::vector<EdgeUse> uses;
    uses.reserve(3 * stats.kept_triangles);
    for (std::size_t t = 0; t < stats.kept_triangles; ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            std::uint64_t a = out.triangles[3 * t + k];
            std::uint64_t b = out.triangles[3 * t + (k + 1) % 3];
            if (a > b) std::swap(a, b);
            const std::uint64_t opposite = out.triangles[3 * t + (k + 2) % 3];
            uses.push_back({(a << 32) | b, (opposite << 32) | (3 * t + k)});
        }
    }
    std::sort(uses.begin(), uses.end());
    out.opposite.resize(uses.size());
    out.opposite_triangle.resize(uses.size());
    out.triangle_edges.resize(uses.size());
    for (std::size_t k = 0; k < uses.size(); ++k) {
        if (k == 0 || uses[k].key != uses[k - 1].key) {
            Edge e;
            e.a = static_cast<std::uint32_t>(uses[k].key >> 32);
            e.b = static_cast<std::uint32_t>(uses[k].key & 0xffffffffu);
            e.first = static_cast<std::uint32_t>(k);
            out.edges.push_back(e);
        }
        Edge& e = out.edges.back();
        ++e.count;
        const auto slot = static_cast<std::uint32_t>(uses[k].payload & 0xffffffffu);
        out.opposite[k] = static_cast<std::uint32_t>(uses[k].payload >> 32);
        out.opposite_triangle[k] = slot / 3;
        out.triangle_edges[slot] = static_cast<std::uint32_t>(out.edges.size() - 1);
    }
    stats.edges = out.edges.size();
    for (const Edge& e : out.edges) {
        if (e.count == 1) ++stats.boundary_edges;
        if (e.count == 2) ++stats.manifold_edges;
        if (e.count >= 3) ++stats.non_manifold_edges;
        stats.max_opposites = std::max<std::size_t>(stats.max_opposites, e.count);
    }
    return out;
}

}  // namespace lixel::volumes
