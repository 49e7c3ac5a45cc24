// Sides by multiplicity, caps by reference-edge facing (paper 001 §2.2-2.3).
#include <lixel/volumes/extrusion.h>

#include <cstdlib>

namespace lixel::volumes {

VolumeMesh ExtrudeSilhouetteVolume(const EdgeAdjacency& adjacency,
                                   std::span<const int> multiplicity, const Vec4& light,
                                   Caps caps) {
    VolumeMesh out;
    auto finite = [&](std::uint32_t w) {
        return Eigen::Vector4d(adjacency.points[w].x(), adjacency.points[w].y(),
                               adjacency.points[w].z(), 1.0);
    };
    auto infinite = [&](std::uint32_t w) {
        return AtInfinity(adjacency.points[w].cast<double>(), light);
    };
    for (std::size_t i = 0; i < adjacency.edges.size(); ++i) {
        const int m = multiplicity[i];
        if (m == 0) continue;
        const Edge& e = adjacency.edges[i];
        // m > 0: the light-facing windings traverse a -> b, so the side, which shares the edge
        // with the light cap, traverses b -> a: quad (b, a, a_inf, b_inf).
        const std::uint32_t p = m > 0 ? e.b : e.a;
        const std::uint32_t q = m > 0 ? e.a : e.b;
        const std::uint32_t v0 = out.Add(finite(p));
        const std::uint32_t v1 = out.Add(finite(q));
        const std::uint32_t v2 = out.Add(infinite(q));
        const std::uint32_t v3 = out.Add(infinite(p));
        for (int k = 0; k < std::abs(m); ++k) {
            out.Side(v0, v1, v2);
            out.Side(v0, v2, v3);
        }
    }
    if (caps == Caps::kNone) return out;
    for (std::size_t t = 0; t < adjacency.source.size(); ++t) {
        const int facing = TriangleFacing(adjacency, t, light);
        if (facing == 0) continue;  // the light lies in its plane: its volume is empty
        std::uint32_t w[3] = {adjacency.triangles[3 * t], adjacency.triangles[3 * t + 1],
                              adjacency.triangles[3 * t + 2]};
        if (facing < 0) std::swap(w[1], w[2]);  // light-facing winding
        const std::uint32_t f0 = out.Add(finite(w[0]));
        const std::uint32_t f1 = out.Add(finite(w[1]));
        const std::uint32_t f2 = out.Add(finite(w[2]));
        out.Cap(f0, f1, f2);
        const std::uint32_t i0 = out.Add(infinite(w[0]));
        const std::uint32_t i1 = out.Add(infinite(w[1]));
        const std::uint32_t i2 = out.Add(infinite(w[2]));
        out.Cap(i0, i2, i1);  // the dark cap faces away from the light
    }
    return out;
}

int ExtrusionCorner(int column, int row) noexcept {
    // Paper 001, Alg. 5, with a = column and b = row.
    const int id = column * 2 + row;
    const int t = (id % 2) ^ ((id / 4) % 2);
    const int l = ((id + 2) / 4) % 2;
    return t + l * 2;
}

std::vector<std::array<int, 4>> TessellatedSideQuads(int m) {
    std::vector<std::array<int, 4>> quads;
    const int segments = 2 * std::abs(m) - 1;
    for (int c = 0; c < segments; ++c) {
        quads.push_back({ExtrusionCorner(c, 0), ExtrusionCorner(c + 1, 0),
                         ExtrusionCorner(c + 1, 1), ExtrusionCorner(c, 1)});
    }
    return quads;
}

}  // namespace lixel::volumes
