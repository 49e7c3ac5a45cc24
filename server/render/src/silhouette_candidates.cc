// Silhouette candidates: the triangles whose geometry-shader run may emit an edge for a light.
#include <lixel/render/adjacency.h>
#include <lixel/render/silhouette_candidates.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace lixel::render {
namespace {

// Absolute slack for a GPU that flushes denormals: each flushed product loses under FLT_MIN.
constexpr double kFlushSlack = 64.0 * std::numeric_limits<float>::min();

Eigen::Vector3d PositionOf(std::span<const float> positions, std::uint32_t vertex) {
    const std::size_t i = 3 * static_cast<std::size_t>(vertex);
    return {positions[i], positions[i + 1], positions[i + 2]};
}

// Whether the shader's vec3 `==` may hold for two vertices: bitwise-equal up to the sign of
// zero, or equal once a GPU flushes denormals to zero.
bool MayCompareEqual(std::span<const float> positions, std::uint32_t a, std::uint32_t b) {
    for (std::size_t k = 0; k < 3; ++k) {
        const float x = positions[3 * static_cast<std::size_t>(a) + k];
        const float y = positions[3 * static_cast<std::size_t>(b) + k];
        constexpr float kMin = std::numeric_limits<float>::min();
        if (!(x == y || (std::abs(x) < kMin && std::abs(y) < kMin))) return false;
    }
    return true;
}

}  // namespace

SilhouetteCandidates SilhouetteCandidates::Build(std::span<const float> positions,
                                                 std::span<const std::uint32_t> adjacency,
                                                 std::span<const std::uint32_t> neighbours) {
    SilhouetteCandidates out;
    const std::size_t triangles = adjacency.size() / 6;
    out.faces_.resize(triangles);
    out.across_.resize(3 * triangles);
    out.adjacency_.assign(adjacency.begin(), adjacency.end());
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t* v = &adjacency[6 * t];
        // The shader's own facing: faces_light(p[0], p[2], p[4]).
        const Eigen::Vector3d p0 = PositionOf(positions, v[0]);
        const Eigen::Vector3d p2 = PositionOf(positions, v[2]);
        const Eigen::Vector3d p4 = PositionOf(positions, v[4]);
        const Eigen::Vector3d n = (p2 - p0).cross(p4 - p0);
        const double longest = std::sqrt(
            std::max({(p2 - p0).squaredNorm(), (p4 - p0).squaredNorm(), (p4 - p2).squaredNorm()}));
        Face& f = out.faces_[t];
        f.normal = n.cast<float>();
        f.offset = static_cast<float>(n.dot(p0));
        f.edge2 = static_cast<float>(longest * longest);
        f.reach = static_cast<float>(p0.norm() + longest);

        bool always = false;
        for (std::size_t k = 0; k < 3 && !always; ++k) {
            const std::uint32_t across = v[2 * k + 1];
            const std::uint32_t own_opposite = v[(2 * k + 4) % 6];
            const std::uint32_t nb = neighbours[3 * t + k];
            // The shader's boundary test compares positions, not indices: a folded neighbour
            // whose far vertex sits on the own opposite vertex is a boundary to it as well.
            if (nb == kNoNeighbour || MayCompareEqual(positions, across, own_opposite)) {
                always = true;
                break;
            }
            // faces_light(a, across, b) is the neighbour's own plane, oriented as the neighbour
            // is when it runs the shared edge b -> a (a consistently wound mesh), reversed when
            // it runs a -> b.
            const std::uint32_t other = nb / 3;
            const std::uint32_t slot = nb % 3;
            const std::uint32_t b = v[(2 * k + 2) % 6];
            const std::uint32_t other_start =
                adjacency[6 * static_cast<std::size_t>(other) + 2 * slot];
            const bool same_way = PositionOf(positions, other_start) != PositionOf(positions, b);
            out.across_[3 * t + k] = (other << 1) | (same_way ? kReversed : 0u);
        }
        if (always) out.across_[3 * t] = kAlwaysDrawn;
    }
    return out;
}

void SilhouetteCandidates::Select(const Eigen::Vector4f& light,
                                  std::vector<std::uint32_t>& out) const {
    const Eigen::Vector3d l = light.head<3>().cast<double>();
    const double w = light.w();
    const double l_norm = l.norm();
    const std::size_t triangles = faces_.size();
    // +1 faces the light whatever the shader's rounding, -1 faces away, 0 undecided.
    std::vector<std::int8_t> facing(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const Face& f = faces_[t];
        // faces_light: n . (l_xyz - l_w p0) = n . l_xyz - l_w (n . p0).
        const double s = f.normal.cast<double>().dot(l) - w * f.offset;
        const double r = l_norm + std::abs(w) * f.reach;
        const double tolerance = kFacingTolerance * f.edge2 * r + kFlushSlack * (1.0 + r);
        facing[t] = s > tolerance ? 1 : (s < -tolerance ? -1 : 0);
    }
    out.clear();
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t* across = &across_[3 * t];
        bool draw = across[0] == kAlwaysDrawn;
        // An edge is emitted only when this triangle faces the light and the neighbour does
        // not (silhouette_map.geom): nothing to emit if this one surely faces away, or if every
        // neighbour surely faces the light.
        if (!draw && facing[t] != -1) {
            for (int k = 0; k < 3 && !draw; ++k) {
                const int f = facing[across[k] >> 1];
                draw = ((across[k] & kReversed) ? -f : f) != 1;
            }
        }
        if (draw) out.insert(out.end(), &adjacency_[6 * t], &adjacency_[6 * t + 6]);
    }
}

}  // namespace lixel::render
