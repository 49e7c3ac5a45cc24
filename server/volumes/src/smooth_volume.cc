// Sides, gap strips and caps of a smooth shadow volume, on shared vertices and without
// T-junctions (issue 16.4): the lit caps carry every point the strips and the neighbouring caps
// put on their border.
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_volume.h>

#include <algorithm>
#include <array>
#include <bit>
#include <map>
#include <unordered_map>

#include "silhouette_trace.h"

namespace lixel::volumes {
namespace {

Eigen::Vector4d Finite(const Vec3& p) { return {p.x(), p.y(), p.z(), 1.0}; }

// Bit pattern of a coordinate, -0 and +0 as one.
std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x + 0.0); }

using PointKey = std::array<std::uint64_t, 3>;
PointKey KeyOf(const Vec3& p) { return {Bits(p.x()), Bits(p.y()), Bits(p.z())}; }

struct KeyHash {
    std::size_t operator()(const std::array<std::uint64_t, 4>& k) const noexcept {
        std::size_t h = 0;
        for (const std::uint64_t x : k)
            h = (h ^ std::hash<std::uint64_t>()(x)) * 0x9e3779b97f4a7c15ull;
        return h;
    }
};

// One vertex per homogeneous position, and no triangle with a repeated vertex (a crease
// corner's zero-length loop edge makes some strip triangles collapse).
class Builder {
  public:
    explicit Builder(VolumeMesh& out) : out_(out) {}

    std::uint32_t Vertex(const Eigen::Vector4d& v) {
        const std::array<std::uint64_t, 4> key = {Bits(v.x()), Bits(v.y()), Bits(v.z()),
                                                  Bits(v.w())};
        const auto [it, fresh] = ids_.emplace(key, 0u);
        if (fresh) it->second = out_.Add(v);
        return it->second;
    }
    void Side(const Eigen::Vector4d& a, const Eigen::Vector4d& b, const Eigen::Vector4d& c) {
        const std::uint32_t i = Vertex(a), j = Vertex(b), k = Vertex(c);
        if (i != j && j != k && k != i) out_.Side(i, j, k);
    }
    void Cap(const Eigen::Vector4d& a, const Eigen::Vector4d& b, const Eigen::Vector4d& c) {
        const std::uint32_t i = Vertex(a), j = Vertex(b), k = Vertex(c);
        if (i != j && j != k && k != i) out_.Cap(i, j, k);
    }

  private:
    VolumeMesh& out_;
    std::unordered_map<std::array<std::uint64_t, 4>, std::uint32_t, KeyHash> ids_;
};

// The bases of the vertices that subdivision put strictly inside each accurate segment of the
// loops, keyed by the segment's end bases in loop direction: the lit caps insert them on the
// border they share with the gap strips.
using Intermediates = std::map<std::pair<PointKey, PointKey>, std::vector<Vec3>>;

Intermediates SegmentIntermediates(const SmoothSilhouette& silhouette) {
    Intermediates out;
    for (const SmoothLoop& loop : silhouette.loops) {
        const std::size_t n = loop.vertices.size();
        if (!loop.closed || n == 0) continue;
        for (std::size_t i = 0; i < n;) {
            std::size_t j = i + 1;
            while (j < n && loop.vertices[j].segment == loop.vertices[i].segment) ++j;
            std::vector<Vec3> inside;
            for (std::size_t k = i + 1; k < j; ++k) inside.push_back(loop.vertices[k].base);
            const Vec3& to = loop.vertices[j % n].base;
            out.emplace(std::pair(KeyOf(loop.vertices[i].base), KeyOf(to)), std::move(inside));
            i = j;
        }
    }
    return out;
}

struct PolygonVertex {
    Vec3 point;
    bool original;  // a corner of the clipped triangle (a mesh corner or a crossing)
};

class CapBuilder {
  public:
    CapBuilder(const Mesh& mesh, const EdgeAdjacency& adj, std::span<const double> facing,
               const Intermediates& intermediates)
        : mesh_(mesh), adj_(adj), facing_(facing), intermediates_(intermediates) {}

    // Triangle t clipped to f > 0, in its oriented winding (the one the loops were traced in),
    // as points on the mesh, with every cut point of its edges (any side's crossing) and every
    // subdivided loop base on its border inserted. Crossing points use EdgePoint and
    // CrossingParameter like the loops, so the border is the loops' p' bit for bit.
    std::vector<PolygonVertex> LitPolygon(std::int8_t orientation, std::uint32_t t) const {
        std::vector<PolygonVertex> polygon;
        auto push = [&](const Vec3& p, bool original) {
            if (!polygon.empty() && KeyOf(polygon.back().point) == KeyOf(p)) {
                polygon.back().original = polygon.back().original || original;
                return;
            }
            polygon.push_back({p, original});
        };
        for (int k = 0; k < 3; ++k) {
            const int c = detail::OrientedCorner(orientation, k);
            const int c1 = detail::OrientedCorner(orientation, (k + 1) % 3);
            const bool lit = Facing(t, c) > 0.0;
            const bool lit1 = Facing(t, c1) > 0.0;
            const std::uint32_t e =
                adj_.triangle_edges[3 * t + detail::OrientedEdgeSlot(orientation, k)];
            const bool forward = adj_.triangles[3 * t + c] == adj_.edges[e].a;
            const double x0 = forward ? 0.0 : 1.0;  // corner c as a parameter on e
            const double x1 = 1.0 - x0;
            if (lit) push(adj_.points[adj_.triangles[3 * t + c]].cast<double>(), true);
            if (lit && lit1) Cuts(e, x0, x1, push);
            if (lit != lit1) {
                const double fa = forward ? Facing(t, c) : Facing(t, c1);
                const double fb = forward ? Facing(t, c1) : Facing(t, c);
                const double x = CrossingParameter(fa, fb);
                if (lit) Cuts(e, x0, x, push);
                push(EdgePoint(adj_, e, x), true);
                if (lit1) Cuts(e, x, x1, push);
            }
        }
        if (polygon.size() > 1 && KeyOf(polygon.front().point) == KeyOf(polygon.back().point)) {
            polygon.front().original = polygon.front().original || polygon.back().original;
            polygon.pop_back();
        }
        // The strips' subdivided bases, on chords and on edge pieces alike.
        std::vector<PolygonVertex> out;
        for (std::size_t i = 0; i < polygon.size(); ++i) {
            const Vec3& p = polygon[i].point;
            const Vec3& q = polygon[(i + 1) % polygon.size()].point;
            out.push_back(polygon[i]);
            const auto it = intermediates_.find({KeyOf(p), KeyOf(q)});
            if (it == intermediates_.end()) continue;
            for (const Vec3& b : it->second) out.push_back({b, false});
        }
        return out;
    }

  private:
    double Facing(std::uint32_t t, int corner) const {
        return facing_[mesh_.indices[3 * static_cast<std::size_t>(adj_.source[t]) + corner]];
    }

    // The crossings of every side of edge e strictly between parameters from and to, in order.
    template <class Push>
    void Cuts(std::uint32_t e, double from, double to, Push& push) const {
        const Edge& edge = adj_.edges[e];
        std::vector<double> cuts;
        for (std::uint32_t k = edge.first; k < edge.first + edge.count; ++k) {
            const std::uint32_t side = adj_.opposite_triangle[k];
            double fa = 0.0, fb = 0.0;
            for (int c = 0; c < 3; ++c) {
                if (adj_.triangles[3 * side + c] == edge.a) fa = Facing(side, c);
                if (adj_.triangles[3 * side + c] == edge.b) fb = Facing(side, c);
            }
            if ((fa > 0.0) == (fb > 0.0)) continue;
            const double x = CrossingParameter(fa, fb);
            if (x > std::min(from, to) && x < std::max(from, to)) cuts.push_back(x);
        }
        std::sort(cuts.begin(), cuts.end());
        if (from > to) std::reverse(cuts.begin(), cuts.end());
        for (const double x : cuts) push(EdgePoint(adj_, e, x), false);
    }

    const Mesh& mesh_;
    const EdgeAdjacency& adj_;
    std::span<const double> facing_;
    const Intermediates& intermediates_;
};

// A fan over a convex polygon. Without inserted points, from its first corner; with them (they
// are collinear with their side's corners), from the centroid of the corners, which lies strictly
// inside, so no vertex can lie on a fan edge. (A fan from a corner would put degenerate or, next
// to a crossing a hair from a mesh corner, nearly degenerate triangles along the chord.)
template <class Emit>
void Triangulate(const std::vector<PolygonVertex>& polygon, Emit&& emit) {
    const std::size_t n = polygon.size();
    if (n < 3) return;
    const bool inserted = std::any_of(polygon.begin(), polygon.end(),
                                      [](const PolygonVertex& v) { return !v.original; });
    if (!inserted) {
        for (std::size_t k = 1; k + 1 < n; ++k) {
            emit(polygon[0].point, polygon[k].point, polygon[k + 1].point);
        }
        return;
    }
    Vec3 centre = Vec3::Zero();
    int originals = 0;
    for (const PolygonVertex& v : polygon) {
        if (!v.original) continue;
        centre += v.point;
        ++originals;
    }
    if (originals == 0) return;
    centre /= originals;
    for (std::size_t k = 0; k < n; ++k) emit(centre, polygon[k].point, polygon[(k + 1) % n].point);
}

}  // namespace

VolumeMesh ExtrudeSmoothVolume(const Mesh& mesh, const EdgeAdjacency& adjacency,
                               const SmoothSilhouette& silhouette, const Vec4& light, Caps caps) {
    VolumeMesh out;
    Builder build(out);
    const Result<Vec4> normalized = NormalizeLight(light);
    const Vec4 l = normalized.ok() ? *normalized : light;
    for (const SmoothLoop& loop : silhouette.loops) {
        const std::size_t n = loop.vertices.size();
        const std::size_t spans = loop.closed ? n : (n == 0 ? 0 : n - 1);
        for (std::size_t i = 0; i < spans; ++i) {
            const SmoothVertex& a = loop.vertices[i];
            const SmoothVertex& b = loop.vertices[(i + 1) % n];
            // R's border runs a -> b, so the strip and the side run b -> a (extrusion.cc).
            const Eigen::Vector4d pa = Finite(a.position), pb = Finite(b.position);
            const Eigen::Vector4d qa = Finite(a.base), qb = Finite(b.base);
            const Eigen::Vector4d ia = AtInfinity(a.position, l), ib = AtInfinity(b.position, l);
            build.Side(qb, qa, pa);  // gap strip (paper 002 Fig. 6)
            build.Side(qb, pa, pb);
            build.Side(pb, pa, ia);  // side
            build.Side(pb, ia, ib);
            if (caps == Caps::kNone) continue;
            const Eigen::Vector4d ja = AtInfinity(a.base, l), jb = AtInfinity(b.base, l);
            build.Cap(ib, ia, ja);  // the strip at infinity, reversed
            build.Cap(ib, ja, jb);
        }
    }
    if (caps == Caps::kNone) return out;
    const std::vector<double> facing = FacingValues(mesh, l);
    const Intermediates intermediates = SegmentIntermediates(silhouette);
    const CapBuilder caps_of(mesh, adjacency, facing, intermediates);
    for (std::uint32_t t = 0; t < adjacency.source.size(); ++t) {
        const std::int8_t orientation = silhouette.orientation.size() == adjacency.source.size()
                                            ? silhouette.orientation[t]
                                            : std::int8_t{1};
        Triangulate(caps_of.LitPolygon(orientation, t),
                    [&](const Vec3& p, const Vec3& q, const Vec3& r) {
                        build.Cap(Finite(p), Finite(q), Finite(r));
                        build.Cap(AtInfinity(p, l), AtInfinity(r, l), AtInfinity(q, l));
                    });
    }
    return out;
}

}  // namespace lixel::volumes
