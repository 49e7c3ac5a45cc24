// Steps (b) and (c) of paper 002 over the loops of silhouette_trace.cc.
#include <lixel/volumes/hermite.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/orientation.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <cmath>
#include <string>

#include "silhouette_trace.h"

namespace lixel::volumes {
namespace {

using detail::TracePoint;

bool SamePoint(const TracePoint& a, const TracePoint& b) {
    return a.key == b.key && a.normal == b.normal && a.displaced == b.displaced;
}

// One loop vertex after step (a)/(b), with whether the edge to the next one is a crease's
// zero-length edge.
struct LoopPoint {
    TracePoint point;
    bool corner = false;
};

std::vector<LoopPoint> LoopPoints(const detail::TracedLoop& loop) {
    std::vector<LoopPoint> points;
    const auto& s = loop.segments;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (i > 0 && !SamePoint(s[i - 1].to, s[i].from)) points.push_back({s[i - 1].to, true});
        points.push_back({s[i].from, false});
    }
    if (!s.empty()) {
        if (!loop.closed) {
            points.push_back({s.back().to, false});
        } else if (!SamePoint(s.back().to, s.front().from)) {
            points.push_back({s.back().to, true});
        }
    }
    return points;
}

// The points emitted so far over all loops, against SmoothOptions::max_points.
struct PointCount {
    std::size_t limit = 0;  // 0: no bound
    std::size_t emitted = 0;
    bool over = false;  // a point past the limit was asked for: the silhouette is refused
};

struct Subdivider {
    const SmoothOptions& options;
    const HermiteSegment& curve;
    const LoopPoint& from;
    const LoopPoint& to;
    std::uint32_t segment;
    SmoothLoop& loop;
    SmoothStats& stats;
    PointCount& count;

    void Emit(double u, bool corner) const {
        if (count.limit != 0 && count.emitted == count.limit) {
            count.over = true;
            return;
        }
        ++count.emitted;
        SmoothVertex v;
        const Vec3 n = (1.0 - u) * from.point.normal + u * to.point.normal;
        v.normal = n.norm() > 0.0 ? Vec3(n.normalized()) : from.point.normal;
        v.position = curve.At(u) - options.normal_offset * v.normal;
        v.base = (1.0 - u) * from.point.base + u * to.point.base;
        v.segment = segment;
        v.u = u;
        v.corner = corner;
        loop.vertices.push_back(v);
    }

    // Paper 002, Listing 1, on the parameter interval [u0, u1] of one cubic. Listing 1 averages
    // the end tangents for the halves; evaluating the parent cubic instead keeps every inserted
    // vertex on the segment's Hermite curve, so the epsilon test is that curve's own flatness.
    void Subdivide(double u0, double u1, const Vec3& p0, const Vec3& p1, int depth) const {
        if (count.over) return;  // refused: nothing more is kept
        const double um = 0.5 * (u0 + u1);
        const Vec3 p = curve.At(um);
        if ((0.5 * (p0 + p1) - p).norm() > options.epsilon) {
            if (depth < options.max_depth) {
                Subdivide(u0, um, p0, p, depth + 1);
                Subdivide(um, u1, p, p1, depth + 1);
                return;
            }
            ++stats.depth_limited;
        }
        Emit(u0, false);
    }
};

Result<bool> Validate(const Mesh& mesh, const EdgeAdjacency& adjacency, const Vec4& light,
                      const SmoothOptions& options) {
    if (mesh.normals.size() != mesh.positions.size()) {
        return Error{"mesh.normals", std::to_string(mesh.normals.size()) + " normals for " +
                                         std::to_string(mesh.positions.size()) +
                                         " vertices; smooth silhouettes need one per vertex"};
    }
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        if (!mesh.normals[i].allFinite() || mesh.normals[i].squaredNorm() == 0.0f) {
            return Error{"mesh.normals[" + std::to_string(i) + "]", "zero or not finite"};
        }
    }
    if (adjacency.welded.size() != mesh.positions.size() ||
        (!adjacency.source.empty() && adjacency.source.back() >= mesh.TriangleCount())) {
        return Error{"adjacency", "not built from this mesh"};
    }
    if (auto l = NormalizeLight(light); !l) return l.error();
    if (!(options.epsilon > 0.0) || !std::isfinite(options.epsilon)) {
        return Error{"options.epsilon", "must be finite and > 0"};
    }
    if (!(options.normal_offset >= 0.0) || !std::isfinite(options.normal_offset)) {
        return Error{"options.normal_offset", "must be finite and >= 0"};
    }
    if (options.max_depth < 0 || options.max_depth > 30) {
        return Error{"options.max_depth", std::to_string(options.max_depth) + " outside [0, 30]"};
    }
    return true;
}

}  // namespace

std::vector<double> FacingValues(const Mesh& mesh, const Vec4& light) {
    std::vector<double> f(mesh.positions.size());
    const Vec3 lxyz = light.head<3>();
    for (std::size_t i = 0; i < f.size(); ++i) {
        const Vec3 n = mesh.normals[i].cast<double>().normalized();
        f[i] = n.dot(lxyz - light.w() * mesh.positions[i].cast<double>());
    }
    return f;
}

Vec3 EdgePoint(const EdgeAdjacency& adjacency, std::uint32_t edge, double x) {
    const Edge& e = adjacency.edges[edge];
    const Vec3 a = adjacency.points[e.a].cast<double>();
    const Vec3 b = adjacency.points[e.b].cast<double>();
    if (x == 0.0) return a;
    if (x == 1.0) return b;
    return a + x * (b - a);
}

Result<SmoothSilhouette> ComputeSmoothSilhouette(const Mesh& mesh, const EdgeAdjacency& adjacency,
                                                 const Vec4& light, const SmoothOptions& options) {
    if (auto ok = Validate(mesh, adjacency, light, options); !ok) return ok.error();
    const Vec4 l = *NormalizeLight(light);
    std::vector<Vec3> normals(mesh.normals.size());
    for (std::size_t i = 0; i < normals.size(); ++i) {
        normals[i] = mesh.normals[i].cast<double>().normalized();
    }
    const std::vector<double> facing = FacingValues(mesh, l);
    auto orientation = OrientTriangles(mesh, adjacency);
    if (!orientation) return orientation.error();
    const auto loops = detail::ChainLoops(
        detail::BoundarySegments(mesh, adjacency, normals, facing, *orientation, options.displace));

    SmoothSilhouette out;
    out.orientation = std::move(orientation.value());
    PointCount emitted{options.max_points};
    const auto refused = [&] {
        return Error{"options.max_points",
                     "subdividing to epsilon = " + ShortestText(options.epsilon) +
                         " makes more than " + std::to_string(options.max_points) + " points"};
    };
    for (const detail::TracedLoop& traced : loops) {
        const std::vector<LoopPoint> points = LoopPoints(traced);
        SmoothLoop loop;
        loop.closed = traced.closed;
        if (!traced.closed) ++out.stats.open_chains;
        out.stats.accurate_points += points.size();
        const std::size_t count = points.size();
        const std::size_t spans = traced.closed ? count : count - 1;
        for (std::size_t i = 0; i < count; ++i) {
            const LoopPoint& from = points[i];
            if (i >= spans) {  // an open chain's last point
                const HermiteSegment none{from.point.displaced, from.point.displaced, Vec3::Zero(),
                                          Vec3::Zero()};
                const auto segment = static_cast<std::uint32_t>(out.segments.size());
                out.segments.push_back({none.p0, none.p1, none.t0, none.t1});
                Subdivider{options, none, from, from, segment, loop, out.stats, emitted}.Emit(
                    0.0, false);
                if (emitted.over) return refused();
                continue;
            }
            const LoopPoint& to = points[(i + 1) % count];
            const auto segment = static_cast<std::uint32_t>(out.segments.size());
            HermiteSegment curve{from.point.displaced, to.point.displaced, Vec3::Zero(),
                                 Vec3::Zero()};
            if (!from.corner) {
                curve = HermiteSegment::FromNormals(from.point.displaced, from.point.normal,
                                                    to.point.displaced, to.point.normal);
            }
            out.segments.push_back({curve.p0, curve.p1, curve.t0, curve.t1});
            const Subdivider sub{options, curve, from, to, segment, loop, out.stats, emitted};
            if (from.corner) {
                ++out.stats.crease_corners;
                sub.Emit(0.0, true);
            } else if (options.subdivide) {
                sub.Subdivide(0.0, 1.0, curve.p0, curve.p1, 0);
            } else {
                sub.Emit(0.0, false);
            }
            if (emitted.over) return refused();
        }
        out.stats.output_points += loop.vertices.size();
        out.loops.push_back(std::move(loop));
    }
    return out;
}

}  // namespace lixel::volumes
