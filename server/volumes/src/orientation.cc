// Breadth-first propagation of windings across manifold edges.
#include <lixel/volumes/orientation.h>

#include <string>

namespace lixel::volumes {
namespace {

// +1 when kept triangle t traverses edge e from e.a to e.b in its input winding, -1 otherwise.
int Direction(const EdgeAdjacency& adj, std::uint32_t t, std::uint32_t e) {
    for (int slot = 0; slot < 3; ++slot) {
        if (adj.triangle_edges[3 * t + slot] == e) {
            return adj.triangles[3 * t + slot] == adj.edges[e].a ? 1 : -1;
        }
    }
    return 0;  // unreachable: e is one of t's edges
}

// n_tri . (n_a + n_b + n_c) in t's input winding, n_tri unnormalised (twice the area).
double NormalAgreement(const Mesh& mesh, const EdgeAdjacency& adj, std::uint32_t t) {
    const Vec3 a = adj.points[adj.triangles[3 * t]].cast<double>();
    const Vec3 b = adj.points[adj.triangles[3 * t + 1]].cast<double>();
    const Vec3 c = adj.points[adj.triangles[3 * t + 2]].cast<double>();
    Vec3 n = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.indices[3 * static_cast<std::size_t>(adj.source[t]) + k];
        n += mesh.normals[v].cast<double>().normalized();
    }
    return (b - a).cross(c - a).dot(n);
}

}  // namespace

Result<std::vector<std::int8_t>> OrientTriangles(const Mesh& mesh, const EdgeAdjacency& adj) {
    const std::size_t count = adj.source.size();
    const bool normals = mesh.normals.size() == mesh.positions.size();
    std::vector<std::int8_t> orientation(count, 0);
    std::vector<std::uint32_t> component;
    for (std::uint32_t seed = 0; seed < count; ++seed) {
        if (orientation[seed] != 0) continue;
        orientation[seed] = 1;
        component.assign(1, seed);
        for (std::size_t next = 0; next < component.size(); ++next) {
            const std::uint32_t t = component[next];
            for (int slot = 0; slot < 3; ++slot) {
                const std::uint32_t e = adj.triangle_edges[3 * t + slot];
                const Edge& edge = adj.edges[e];
                if (edge.count != 2) continue;
                const std::uint32_t u = adj.opposite_triangle[edge.first] == t
                                            ? adj.opposite_triangle[edge.first + 1]
                                            : adj.opposite_triangle[edge.first];
                // Consistent: the two traverse the edge in opposite directions once oriented.
                const int want = -orientation[t] * Direction(adj, t, e) * Direction(adj, u, e);
                if (orientation[u] == 0) {
                    orientation[u] = static_cast<std::int8_t>(want);
                    component.push_back(u);
                } else if (orientation[u] != want) {
                    return Error{"mesh", "'" + mesh.name +
                                             "' is not orientable: no winding agrees across "
                                             "every edge of two triangles (input triangles " +
                                             std::to_string(adj.source[t]) + " and " +
                                             std::to_string(adj.source[u]) + ")"};
                }
            }
        }
        if (!normals) continue;
        double agreement = 0.0;
        for (std::uint32_t t : component)
            agreement += orientation[t] * NormalAgreement(mesh, adj, t);
        if (agreement < 0.0) {
            for (std::uint32_t t : component)
                orientation[t] = static_cast<std::int8_t>(-orientation[t]);
        }
    }
    return orientation;
}

}  // namespace lixel::volumes
