// Triangle meshes as the solver and every later stage see them: indexed triangles in world
// units, optionally with per-vertex normals. No GL here; the renderer uploads these as they are.
#pragma once

#include <lixel/solver/types.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace lixel {

struct Mesh {
    std::string name;
    std::vector<Eigen::Vector3f> positions;  // world units
    std::vector<Eigen::Vector3f> normals;    // unit, per vertex; empty or positions.size()
    std::vector<std::uint32_t> indices;      // three per triangle, counter-clockwise = front
    // A closed, consistently oriented solid: second-depth needs no bias on it (paper 003 §3.3).
    bool closed = false;

    std::size_t TriangleCount() const { return indices.size() / 3; }
    Aabb Bounds() const;
};

inline Aabb Mesh::Bounds() const {
    Aabb box{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (const Eigen::Vector3f& p : positions) {
        box.min = box.min.cwiseMin(p.cast<double>());
        box.max = box.max.cwiseMax(p.cast<double>());
    }
    return box;
}

}  // namespace lixel
