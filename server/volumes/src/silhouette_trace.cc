// The lit region's boundary: segments inside triangles where f changes sign (Hertzmann-Zorin
// points on two edges), plus the parts of edges whose sides disagree about R (creases, open
// boundaries, non-manifold fans), found as the net signed coverage of each edge.
#include "silhouette_trace.h"

#include <lixel/volumes/hermite.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <unordered_map>

namespace lixel::volumes::detail {
namespace {

constexpr std::uint64_t kEdgeTag = std::uint64_t{1} << 63;

struct Builder {
    const Mesh& mesh;
    const EdgeAdjacency& adj;
    std::span<const Vec3> normals;
    std::span<const double> facing;
    std::span<const std::int8_t> orientation;
    bool displace;

    std::uint32_t InputVertex(std::uint32_t t, int k) const {
        return mesh.indices[3 * static_cast<std::size_t>(adj.source[t]) + k];
    }
    int Corner(std::uint32_t t, std::uint32_t welded) const {
        for (int k = 0; k < 3; ++k) {
            if (adj.triangles[3 * t + k] == welded) return k;
        }
        return -1;
    }

    // The point at canonical parameter x of edge e as triangle t's side sees it.
    TracePoint Point(std::uint32_t t, std::uint32_t e, double x) const {
        const Edge& edge = adj.edges[e];
        const std::uint32_t ia = InputVertex(t, Corner(t, edge.a));
        const std::uint32_t ib = InputVertex(t, Corner(t, edge.b));
        const Vec3& na = normals[ia];
        const Vec3& nb = normals[ib];
        TracePoint p;
        if (x == 0.0) {
            p.key = {edge.a, 0};
        } else if (x == 1.0) {
            p.key = {edge.b, 0};
        } else {
            p.key = {kEdgeTag | e, std::bit_cast<std::uint64_t>(x)};
        }
        p.base = EdgePoint(adj, e, x);
        Vec3 n = (1.0 - x) * na + x * nb;
        p.normal = n.norm() > 0.0 ? Vec3(n.normalized()) : (x < 0.5 ? na : nb);
        if (displace && x != 0.0 && x != 1.0) {
            const Vec3 a = adj.points[edge.a].cast<double>();
            const Vec3 b = adj.points[edge.b].cast<double>();
            p.displaced = HermiteSegment::FromNormals(a, na, b, nb).At(x);
        } else {
            p.displaced = p.base;
        }
        return p;
    }

    // Triangle t's facing values at edge e's canonical ends.
    std::pair<double, double> EndFacing(std::uint32_t t, const Edge& edge) const {
        return {facing[InputVertex(t, Corner(t, edge.a))],
                facing[InputVertex(t, Corner(t, edge.b))]};
    }

    // +1 when t's oriented winding runs edge e from e.a to e.b.
    int EdgeSign(std::uint32_t t, std::uint32_t e) const {
        int slot = 0;
        while (adj.triangle_edges[3 * t + slot] != e) ++slot;
        const int input = adj.triangles[3 * t + slot] == adj.edges[e].a ? 1 : -1;
        return orientation[t] < 0 ? -input : input;
    }

    void Interior(std::uint32_t t, std::vector<TraceSegment>& out) const {
        double f[3];
        bool in[3];
        for (int k = 0; k < 3; ++k) {
            f[k] = facing[InputVertex(t, OrientedCorner(orientation[t], k))];
            in[k] = f[k] > 0.0;
        }
        if (in[0] == in[1] && in[1] == in[2]) return;
        int exit = -1;
        int enter = -1;
        for (int k = 0; k < 3; ++k) {
            if (in[k] && !in[(k + 1) % 3]) exit = k;
            if (!in[k] && in[(k + 1) % 3]) enter = k;
        }
        auto crossing = [&](int k) {
            const std::uint32_t e = adj.triangle_edges[3 * t + OrientedEdgeSlot(orientation[t], k)];
            const auto [fa, fb] = EndFacing(t, adj.edges[e]);
            return Point(t, e, CrossingParameter(fa, fb));
        };
        // Counter-clockwise around R: leave it on the exit edge, come back on the enter edge.
        // Both at one mesh corner (R meets the triangle only there, CrossingParameter snapped
        // to it): no boundary in this triangle, and no zero-length loop through the corner.
        const TracePoint from = crossing(exit);
        const TracePoint to = crossing(enter);
        if (from.key == to.key) return;
        out.push_back({from, to});
    }

    struct Cover {
        double lo, hi;
        int sign;  // +1: the side's oriented winding runs a -> b
        std::uint32_t triangle;
    };

    void EdgePieces(std::uint32_t e, std::vector<TraceSegment>& out) const {
        const Edge& edge = adj.edges[e];
        // Most edges lie wholly inside or outside R on every side and cancel: decide that
        // without allocating (the common case on a large mesh).
        {
            int full_sum = 0;
            bool trivial = true;
            for (std::uint32_t k = edge.first; k < edge.first + edge.count && trivial; ++k) {
                const std::uint32_t t = adj.opposite_triangle[k];
                const auto [fa, fb] = EndFacing(t, edge);
                if ((fa > 0.0) != (fb > 0.0)) trivial = false;
                if (fa > 0.0 && fb > 0.0) full_sum += EdgeSign(t, e);
            }
            if (trivial && full_sum == 0) return;
        }
        std::vector<Cover> covers;
        for (std::uint32_t k = edge.first; k < edge.first + edge.count; ++k) {
            const std::uint32_t t = adj.opposite_triangle[k];
            const int sign = EdgeSign(t, e);
            const auto [fa, fb] = EndFacing(t, edge);
            const bool ia = fa > 0.0;
            const bool ib = fb > 0.0;
            if (!ia && !ib) continue;
            if (ia && ib) {
                covers.push_back({0.0, 1.0, sign, t});
                continue;
            }
            const double x = CrossingParameter(fa, fb);
            covers.push_back(ia ? Cover{0.0, x, sign, t} : Cover{x, 1.0, sign, t});
        }
        if (covers.empty()) return;
        std::vector<double> cuts = {0.0, 1.0};
        for (const Cover& c : covers) {
            cuts.push_back(c.lo);
            cuts.push_back(c.hi);
        }
        std::sort(cuts.begin(), cuts.end());
        cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
        // Net signed coverage per elementary interval, each its own run: every cut is a vertex of
        // the lit caps on this edge (smooth_volume.cc), so a loop piece must not span one (issue
        // 16.4). (Where sides are consistently wound and at most two, no run spans a cut anyway.)
        int run_net = 0;
        std::uint32_t run_owner = 0;
        double run_lo = 0.0;
        auto flush = [&](double hi) {
            if (run_net == 0) return;
            const TracePoint lo_point = Point(run_owner, e, run_lo);
            const TracePoint hi_point = Point(run_owner, e, hi);
            for (int r = 0; r < std::abs(run_net); ++r) {
                if (run_net > 0) {
                    out.push_back({lo_point, hi_point});
                } else {
                    out.push_back({hi_point, lo_point});
                }
            }
        };
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            int net = 0;
            for (const Cover& c : covers) {
                if (c.lo <= cuts[i] && c.hi >= cuts[i + 1]) net += c.sign;
            }
            std::uint32_t owner = 0;
            for (const Cover& c : covers) {
                if (c.lo <= cuts[i] && c.hi >= cuts[i + 1] && (c.sign > 0) == (net > 0)) {
                    owner = c.triangle;
                    break;
                }
            }
            if (i > 0) flush(cuts[i]);
            run_net = net;
            run_owner = owner;
            run_lo = cuts[i];
        }
        flush(1.0);
    }
};

struct KeyHash {
    std::size_t operator()(const PointKey& k) const noexcept {
        return std::hash<std::uint64_t>()(k.first * 0x9e3779b97f4a7c15ull ^ k.second);
    }
};

}  // namespace

std::vector<TraceSegment> BoundarySegments(const Mesh& mesh, const EdgeAdjacency& adjacency,
                                           std::span<const Vec3> unit_normals,
                                           std::span<const double> facing,
                                           std::span<const std::int8_t> orientation,
                                           bool displace) {
    const Builder builder{mesh, adjacency, unit_normals, facing, orientation, displace};
    std::vector<TraceSegment> out;
    for (std::uint32_t t = 0; t < adjacency.source.size(); ++t) builder.Interior(t, out);
    for (std::uint32_t e = 0; e < adjacency.edges.size(); ++e) builder.EdgePieces(e, out);
    return out;
}

std::vector<TracedLoop> ChainLoops(std::vector<TraceSegment> segments) {
    std::unordered_map<PointKey, std::vector<std::uint32_t>, KeyHash> outgoing;
    for (std::uint32_t i = 0; i < segments.size(); ++i) {
        outgoing[segments[i].from.key].push_back(i);
    }
    std::vector<char> used(segments.size(), 0);
    std::vector<TracedLoop> loops;
    for (std::uint32_t s = 0; s < segments.size(); ++s) {
        if (used[s]) continue;
        TracedLoop loop;
        const PointKey start = segments[s].from.key;
        std::uint32_t current = s;
        for (;;) {
            used[current] = 1;
            loop.segments.push_back(segments[current]);
            const PointKey at = segments[current].to.key;
            if (at == start) break;
            auto it = outgoing.find(at);
            std::uint32_t next = UINT32_MAX;
            if (it != outgoing.end()) {
                for (std::uint32_t candidate : it->second) {
                    if (!used[candidate]) {
                        next = candidate;
                        break;
                    }
                }
            }
            if (next == UINT32_MAX) {
                loop.closed = false;
                break;
            }
            current = next;
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

}  // namespace lixel::volumes::detail
