// Alg. 3/4 over an adjacency: exactly (orient3d.h), or in the shader's float arithmetic.
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/orient3d.h>

#include <algorithm>
#include <utility>

namespace lixel::volumes {
namespace {

// The floats the GPU holds for a welded point: subtracted in double, converted last
// (UploadVolumeScene).
Eigen::Vector3f Relative(const Eigen::Vector3f& p, const Vec3& origin) {
    return (p.cast<double>() - origin).cast<float>();
}

// shadow_volume.tesc: the edge's ends re-ordered if rounding made them compare the other way,
// then Alg. 3 over its opposite points.
int FloatEdgeMultiplicity(const EdgeAdjacency& adj, const Edge& e, const Eigen::Vector4f& l,
                          const Vec3& origin) {
    Eigen::Vector3f a = Relative(adj.points[e.a], origin);
    Eigen::Vector3f b = Relative(adj.points[e.b], origin);
    if (Greater(a, b) > 0) std::swap(a, b);
    int m = 0;
    for (std::uint32_t o : adj.Opposites(e)) {
        m += OppositeContribution<float>(a, b, Relative(adj.points[o], origin), l);
    }
    return m;
}

int FloatFacing(const EdgeAdjacency& adj, std::size_t t, const Eigen::Vector4f& l) {
    std::uint32_t w[3] = {adj.triangles[3 * t], adj.triangles[3 * t + 1], adj.triangles[3 * t + 2]};
    // Welded ids are numbered in Greater order, so sorting ids sorts the corners.
    std::uint32_t s[3] = {w[0], w[1], w[2]};
    std::sort(s, s + 3);
    const int m = CompMultiplicity<float>(adj.points[s[0]], adj.points[s[1]], adj.points[s[2]], l);
    // The sorted order s0 -> s1 -> s2 is an even permutation of the input winding when the
    // input's smallest corner is followed by its middle one.
    const int first = w[0] == s[0] ? 0 : (w[1] == s[0] ? 1 : 2);
    const bool even = w[(first + 1) % 3] == s[1];
    return even ? m : -m;
}

int ExactFacing(const EdgeAdjacency& adj, std::size_t t, const Vec4& l) {
    return LightFacingSign(adj.points[adj.triangles[3 * t]].cast<double>(),
                           adj.points[adj.triangles[3 * t + 1]].cast<double>(),
                           adj.points[adj.triangles[3 * t + 2]].cast<double>(), l);
}

}  // namespace

int TriangleFacing(const EdgeAdjacency& adjacency, std::size_t triangle, const Vec4& light,
                   Arithmetic arithmetic) {
    if (arithmetic == Arithmetic::kFloat) {
        return FloatFacing(adjacency, triangle, light.cast<float>());
    }
    return ExactFacing(adjacency, triangle, light);
}

std::vector<std::int8_t> ComputeFacings(const EdgeAdjacency& adjacency, const Vec4& light,
                                        Arithmetic arithmetic) {
    std::vector<std::int8_t> facing(adjacency.source.size());
    for (std::size_t t = 0; t < facing.size(); ++t) {
        facing[t] = static_cast<std::int8_t>(TriangleFacing(adjacency, t, light, arithmetic));
    }
    return facing;
}

std::vector<int> MultiplicitiesFromFacings(const EdgeAdjacency& adjacency,
                                           std::span<const std::int8_t> facing) {
    std::vector<int> m(adjacency.edges.size(), 0);
    for (std::size_t t = 0; t < facing.size() && t < adjacency.source.size(); ++t) {
        if (facing[t] == 0) continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t e = adjacency.triangle_edges[3 * t + k];
            const bool forward = adjacency.triangles[3 * t + k] == adjacency.edges[e].a;
            m[e] += forward ? facing[t] : -facing[t];
        }
    }
    return m;
}

std::vector<int> ComputeMultiplicities(const EdgeAdjacency& adjacency, const Vec4& light,
                                       Arithmetic arithmetic, const Vec3& origin) {
    if (arithmetic == Arithmetic::kExact) {
        return MultiplicitiesFromFacings(adjacency, ComputeFacings(adjacency, light));
    }
    // VolumePass: the normalized light relative to the origin, in double, then float.
    const Vec4 l = NormalizeLight(light).ok() ? *NormalizeLight(light) : light;
    const Eigen::Vector4f relative(static_cast<float>(l.x() - l.w() * origin.x()),
                                   static_cast<float>(l.y() - l.w() * origin.y()),
                                   static_cast<float>(l.z() - l.w() * origin.z()),
                                   static_cast<float>(l.w()));
    std::vector<int> m(adjacency.edges.size());
    for (std::size_t i = 0; i < m.size(); ++i) {
        m[i] = FloatEdgeMultiplicity(adjacency, adjacency.edges[i], relative, origin);
    }
    return m;
}

std::vector<SilhouetteEdge> ExtractSilhouette(const EdgeAdjacency& adjacency, const Vec4& light,
                                              Arithmetic arithmetic) {
    const std::vector<int> m = ComputeMultiplicities(adjacency, light, arithmetic);
    std::vector<SilhouetteEdge> out;
    for (std::size_t i = 0; i < m.size(); ++i) {
        if (m[i] == 0) continue;
        const Edge& e = adjacency.edges[i];
        out.push_back({adjacency.A(e), adjacency.B(e), m[i], static_cast<std::uint32_t>(i)});
    }
    return out;
}

Result<Vec4> NormalizeLight(const Vec4& light) {
    if (!light.allFinite()) return Error{"light", "not finite"};
    if (light.w() == 0.0) {
        if (light.head<3>().isZero()) return Error{"light", "zero direction (w = 0, xyz = 0)"};
        return light;
    }
    return Vec4(light / light.w());
}

}  // namespace lixel::volumes
