// A shadow volume as plain triangles in homogeneous world coordinates: what the CPU reference
// extrusion produces, what the smooth path hands to GL, and what an engine can draw itself.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lixel::volumes {

// Which closing faces a volume carries. Z-pass needs none; z-fail needs both caps so every
// volume is closed (Everitt and Kilgard).
enum class Caps { kNone, kLightAndDark };

struct VolumeMesh {
    // Homogeneous world points: w = 1 finite, w = 0 at infinity (extruded away from the light).
    std::vector<Eigen::Vector4d> vertices;
    // Three indices per triangle. Winding is consistent over each closed volume: a light cap's
    // front faces the light, so walking into a volume crosses a front face (counted +1 by
    // CountZPass). `sides` are extruded from silhouette edges (and, for smooth silhouettes,
    // the gap strips); `caps` close them for z-fail (light caps, dark caps at infinity).
    std::vector<std::uint32_t> sides;
    std::vector<std::uint32_t> caps;

    std::size_t SideTriangles() const { return sides.size() / 3; }
    std::size_t CapTriangles() const { return caps.size() / 3; }
    std::uint32_t Add(const Eigen::Vector4d& v) {
        vertices.push_back(v);
        return static_cast<std::uint32_t>(vertices.size() - 1);
    }
    void Side(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        sides.insert(sides.end(), {a, b, c});
    }
    void Cap(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        caps.insert(caps.end(), {a, b, c});
    }
};

// The point a finite point p is pushed to, away from a homogeneous light l (paper 001 Eq. 2 and
// Alg. 1): (l_w p - l_xyz, 0).
inline Eigen::Vector4d AtInfinity(const Eigen::Vector3d& p, const Eigen::Vector4d& l) {
    return {l.w() * p.x() - l.x(), l.w() * p.y() - l.y(), l.w() * p.z() - l.z(), 0.0};
}

}  // namespace lixel::volumes
