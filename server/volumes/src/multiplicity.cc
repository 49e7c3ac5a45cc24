// Alg. 3/4 over an adjacency, in double or in the shader's float arithmetic.
#include <lixel/volumes/multiplicity.h>

#include <algorithm>

namespace lixel::volumes {
namespace {

template <class S>
int EdgeMultiplicity(const EdgeAdjacency& adj, const Edge& e, const Eigen::Matrix<S, 4, 1>& l) {
    const Eigen::Matrix<S, 3, 1> a = adj.points[e.a].cast<S>();
    const Eigen::Matrix<S, 3, 1> b = adj.points[e.b].cast<S>();
    int m = 0;
    for (std::uint32_t o : adj.Opposites(e)) {
        m += OppositeContribution<S>(a, b, adj.points[o].cast<S>(), l);
    }
    return m;
}

template <class S>
int Facing(const EdgeAdjacency& adj, std::size_t t, const Eigen::Matrix<S, 4, 1>& l) {
    std::uint32_t w[3] = {adj.triangles[3 * t], adj.triangles[3 * t + 1], adj.triangles[3 * t + 2]};
    // Welded ids are numbered in Greater order, so sorting ids sorts the corners.
    std::uint32_t s[3] = {w[0], w[1], w[2]};
    std::sort(s, s + 3);
    const int m = CompMultiplicity<S>(adj.points[s[0]].cast<S>(), adj.points[s[1]].cast<S>(),
                                      adj.points[s[2]].cast<S>(), l);
    // The sorted order s0 -> s1 -> s2 is an even permutation of the input winding when the
    // input's smallest corner is followed by its middle one.
    const int first = w[0] == s[0] ? 0 : (w[1] == s[0] ? 1 : 2);
    const bool even = w[(first + 1) % 3] == s[1];
    return even ? m : -m;
}

}  // namespace

int TriangleFacing(const EdgeAdjacency& adjacency, std::size_t triangle, const Vec4& light,
                   Arithmetic arithmetic) {
    if (arithmetic == Arithmetic::kFloat) {
        return Facing<float>(adjacency, triangle, light.cast<float>());
    }
    return Facing<double>(adjacency, triangle, light);
}

std::vector<int> ComputeMultiplicities(const EdgeAdjacency& adjacency, const Vec4& light,
                                       Arithmetic arithmetic) {
    std::vector<int> m(adjacency.edges.size());
    if (arithmetic == Arithmetic::kFloat) {
        const Eigen::Vector4f l = light.cast<float>();
        for (std::size_t i = 0; i < m.size(); ++i) {
            m[i] = EdgeMultiplicity<float>(adjacency, adjacency.edges[i], l);
        }
    } else {
        for (std::size_t i = 0; i < m.size(); ++i) {
            m[i] = EdgeMultiplicity<double>(adjacency, adjacency.edges[i], light);
        }
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
