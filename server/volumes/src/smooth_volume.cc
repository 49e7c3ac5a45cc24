// Sides, gap strips and caps of a smooth shadow volume.
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_volume.h>

#include "silhouette_trace.h"

namespace lixel::volumes {
namespace {

Eigen::Vector4d Finite(const Vec3& p) { return {p.x(), p.y(), p.z(), 1.0}; }

// Triangle t clipped to f > 0, in its oriented winding (the one the loops were traced in), as
// points on the mesh. Crossing points use EdgePoint/CrossingParameter like the loops, so the
// cap's border is the loops' p' bit for bit.
std::vector<Vec3> LitPolygon(const Mesh& mesh, const EdgeAdjacency& adj,
                             std::span<const double> facing, std::int8_t orientation,
                             std::uint32_t t) {
    std::vector<Vec3> polygon;
    const std::size_t first = 3 * static_cast<std::size_t>(adj.source[t]);
    for (int k = 0; k < 3; ++k) {
        const int c = detail::OrientedCorner(orientation, k);
        const int c1 = detail::OrientedCorner(orientation, (k + 1) % 3);
        const double f = facing[mesh.indices[first + c]];
        const double f1 = facing[mesh.indices[first + c1]];
        if (f > 0.0) polygon.push_back(adj.points[adj.triangles[3 * t + c]].cast<double>());
        if ((f > 0.0) != (f1 > 0.0)) {
            const std::uint32_t e =
                adj.triangle_edges[3 * t + detail::OrientedEdgeSlot(orientation, k)];
            const bool forward = adj.triangles[3 * t + c] == adj.edges[e].a;
            const double fa = forward ? f : f1;
            const double fb = forward ? f1 : f;
            polygon.push_back(EdgePoint(adj, e, CrossingParameter(fa, fb)));
        }
    }
    return polygon;
}

}  // namespace

VolumeMesh ExtrudeSmoothVolume(const Mesh& mesh, const EdgeAdjacency& adjacency,
                               const SmoothSilhouette& silhouette, const Vec4& light, Caps caps) {
    VolumeMesh out;
    const Result<Vec4> normalized = NormalizeLight(light);
    const Vec4 l = normalized.ok() ? *normalized : light;
    for (const SmoothLoop& loop : silhouette.loops) {
        const std::size_t n = loop.vertices.size();
        const std::size_t spans = loop.closed ? n : (n == 0 ? 0 : n - 1);
        for (std::size_t i = 0; i < spans; ++i) {
            const SmoothVertex& a = loop.vertices[i];
            const SmoothVertex& b = loop.vertices[(i + 1) % n];
            // R's border runs a -> b, so the strip and the side run b -> a (extrusion.cc).
            const std::uint32_t pa = out.Add(Finite(a.position));
            const std::uint32_t pb = out.Add(Finite(b.position));
            const std::uint32_t qa = out.Add(Finite(a.base));
            const std::uint32_t qb = out.Add(Finite(b.base));
            const std::uint32_t ia = out.Add(AtInfinity(a.position, l));
            const std::uint32_t ib = out.Add(AtInfinity(b.position, l));
            out.Side(qb, qa, pa);  // gap strip (paper 002 Fig. 6)
            out.Side(qb, pa, pb);
            out.Side(pb, pa, ia);  // side
            out.Side(pb, ia, ib);
            if (caps == Caps::kNone) continue;
            const std::uint32_t ja = out.Add(AtInfinity(a.base, l));
            const std::uint32_t jb = out.Add(AtInfinity(b.base, l));
            out.Cap(ib, ia, ja);  // the strip at infinity, reversed
            out.Cap(ib, ja, jb);
        }
    }
    if (caps == Caps::kNone) return out;
    const std::vector<double> facing = FacingValues(mesh, l);
    for (std::uint32_t t = 0; t < adjacency.source.size(); ++t) {
        const std::int8_t orientation = silhouette.orientation.size() == adjacency.source.size()
                                            ? silhouette.orientation[t]
                                            : std::int8_t{1};
        const std::vector<Vec3> polygon = LitPolygon(mesh, adjacency, facing, orientation, t);
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
            out.Cap(out.Add(Finite(polygon[0])), out.Add(Finite(polygon[k])),
                    out.Add(Finite(polygon[k + 1])));
            out.Cap(out.Add(AtInfinity(polygon[0], l)), out.Add(AtInfinity(polygon[k + 1], l)),
                    out.Add(AtInfinity(polygon[k], l)));
        }
    }
    return out;
}

}  // namespace lixel::volumes
