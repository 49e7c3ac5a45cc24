// Sides by multiplicity, caps by the facings the multiplicities are the boundary of (paper 001
// §2.2-2.3, issue 16.5).
#include <lixel/volumes/extrusion.h>

#include <algorithm>
#include <cstdlib>
#include <utility>

namespace lixel::volumes {

namespace {

Eigen::Vector4d Finite(const EdgeAdjacency& adjacency, std::uint32_t w) {
    const Eigen::Vector3f& p = adjacency.points[w];
    return {p.x(), p.y(), p.z(), 1.0};
}

Eigen::Vector4d Infinite(const EdgeAdjacency& adjacency, std::uint32_t w, const Vec4& light) {
    return AtInfinity(adjacency.points[w].cast<double>(), light);
}

void AddSides(const EdgeAdjacency& adjacency, std::span<const int> multiplicity, const Vec4& light,
              VolumeMesh& out) {
    for (std::size_t i = 0; i < adjacency.edges.size() && i < multiplicity.size(); ++i) {
        const int m = multiplicity[i];
        if (m == 0) continue;
        const Edge& e = adjacency.edges[i];
        // m > 0: the light-facing windings traverse a -> b, so the side, which shares the edge
        // with the light cap, traverses b -> a: quad (b, a, a_inf, b_inf).
        const std::uint32_t p = m > 0 ? e.b : e.a;
        const std::uint32_t q = m > 0 ? e.a : e.b;
        const std::uint32_t v0 = out.Add(Finite(adjacency, p));
        const std::uint32_t v1 = out.Add(Finite(adjacency, q));
        const std::uint32_t v2 = out.Add(Infinite(adjacency, q, light));
        const std::uint32_t v3 = out.Add(Infinite(adjacency, p, light));
        for (int k = 0; k < std::abs(m); ++k) {
            out.Side(v0, v1, v2);
            out.Side(v0, v2, v3);
        }
    }
}

void AddCaps(const EdgeAdjacency& adjacency, std::span<const std::int8_t> facing, const Vec4& light,
             VolumeMesh& out) {
    for (std::size_t t = 0; t < adjacency.source.size() && t < facing.size(); ++t) {
        if (facing[t] == 0) continue;  // the light lies in its plane: its volume is empty
        std::uint32_t w[3] = {adjacency.triangles[3 * t], adjacency.triangles[3 * t + 1],
                              adjacency.triangles[3 * t + 2]};
        if (facing[t] < 0) std::swap(w[1], w[2]);  // light-facing winding
        const std::uint32_t f0 = out.Add(Finite(adjacency, w[0]));
        const std::uint32_t f1 = out.Add(Finite(adjacency, w[1]));
        const std::uint32_t f2 = out.Add(Finite(adjacency, w[2]));
        out.Cap(f0, f1, f2);
        const std::uint32_t i0 = out.Add(Infinite(adjacency, w[0], light));
        const std::uint32_t i1 = out.Add(Infinite(adjacency, w[1], light));
        const std::uint32_t i2 = out.Add(Infinite(adjacency, w[2], light));
        out.Cap(i0, i2, i1);  // the dark cap faces away from the light
    }
}

}  // namespace

VolumeMesh ExtrudeSilhouetteVolume(const EdgeAdjacency& adjacency,
                                   std::span<const std::int8_t> facing, const Vec4& light,
                                   Caps caps) {
    VolumeMesh out;
    AddSides(adjacency, MultiplicitiesFromFacings(adjacency, facing), light, out);
    if (caps == Caps::kLightAndDark) AddCaps(adjacency, facing, light, out);
    return out;
}

VolumeMesh ExtrudeSilhouetteVolume(const EdgeAdjacency& adjacency,
                                   std::span<const int> multiplicity, const Vec4& light,
                                   Caps caps) {
    VolumeMesh out;
    AddSides(adjacency, multiplicity, light, out);
    if (caps == Caps::kNone) return out;
    // Caps from the facings whose boundary the multiplicities are (issue 16.5: caps decided in
    // double next to float multiplicities left nearly edge-on triangles open).
    std::vector<std::int8_t> facing = ComputeFacings(adjacency, light, Arithmetic::kExact);
    const auto matches = [&](std::span<const std::int8_t> f) {
        const std::vector<int> m = MultiplicitiesFromFacings(adjacency, f);
        return std::equal(m.begin(), m.end(), multiplicity.begin(), multiplicity.end());
    };
    if (!matches(facing)) {
        std::vector<std::int8_t> single = ComputeFacings(adjacency, light, Arithmetic::kFloat);
        if (matches(single)) facing = std::move(single);
    }
    AddCaps(adjacency, facing, light, out);
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
